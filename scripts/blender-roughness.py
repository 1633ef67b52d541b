"""A sphere whose roughness and metalness come from a texture, as users bring them: Blender's Principled BSDF
with one Non-Color image through Separate Color, G to Roughness and B to Metallic, written by Blender's own
glTF exporter as a metallicRoughnessTexture. The texture (16 x 2 texels, Closest: the sampler's NEAREST)
gives 16 bands around the sphere, smooth (roughness 0.08) and rough (0.6) in turn, metal above the equator and
a dielectric below; the base colour is one gold. The sphere is 1 m in radius, 96 segments by 48 rings, smooth.

    blender -b --factory-startup --python scripts/blender-roughness.py -- assets/models/roughness_bands.glb
"""
import sys

import bpy
import numpy as np

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)

width, height = 16, 2
roughness = np.where(np.arange(width) % 2 == 0, 0.08, 0.6)
rgba = np.ones((height, width, 4), np.float32)
rgba[:, :, 1] = roughness
rgba[0, :, 2] = 0.0  # Blender's rows run bottom to top: the southern half a dielectric
rgba[1, :, 2] = 1.0  # the northern half a metal
image = bpy.data.images.new("roughness_bands", width, height, alpha=True)
image.colorspace_settings.name = "Non-Color"
image.pixels.foreach_set(rgba.ravel())
image.file_format = "PNG"
image.pack()

bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=1.0)
sphere = bpy.context.active_object
sphere.name = "roughness bands"
bpy.ops.object.shade_smooth()
material = bpy.data.materials.new("banded gold")
material.use_nodes = True
nodes, links = material.node_tree.nodes, material.node_tree.links
bsdf = nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (1.0, 0.78, 0.34, 1.0)
texture = nodes.new("ShaderNodeTexImage")
texture.image = image
texture.interpolation = "Closest"
separate = nodes.new("ShaderNodeSeparateColor")
links.new(texture.outputs["Color"], separate.inputs["Color"])
links.new(separate.outputs["Green"], bsdf.inputs["Roughness"])
links.new(separate.outputs["Blue"], bsdf.inputs["Metallic"])
sphere.data.materials.append(material)

bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_apply=True)
