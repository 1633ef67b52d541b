"""A leaf card as users bring them: a square plane whose base-colour texture's alpha is a leaf, its
material set to Alpha Clip, written by Blender's own glTF exporter (alphaMode MASK, alphaCutoff 0.5).
The texture is drawn here (a leaf outline, a midrib and side veins); the plane is 1 m across, facing up.

    blender -b --python scripts/blender-leaf.py -- assets/models/leaf.glb
"""
import sys

import bpy
import numpy as np

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)

size = 256
v, u = (np.mgrid[0:size, 0:size] + 0.5) / size  # Blender's rows run bottom to top: v = 0 at the bottom
t = (v - 0.1) / 0.85                              # along the leaf, stem end to tip
half_width = 0.3 * np.sin(np.pi * np.clip(t, 0.0, 1.0)) ** 0.7
across = u - 0.5
blade = (t > 0.0) & (t < 1.0) & (np.abs(across) < half_width)
stem = (v < 0.12) & (np.abs(across) < 0.012)
midrib = np.abs(across) < 0.008
side_veins = np.abs(((v - 0.6 * np.abs(across)) * 9.0) % 1.0 - 0.5) < 0.06
rgba = np.zeros((size, size, 4), np.float32)
rgba[..., 0:3] = (0.10, 0.32, 0.04)
rgba[blade & side_veins] = (0.16, 0.42, 0.07, 0.0)
rgba[blade & midrib] = (0.35, 0.55, 0.15, 0.0)
rgba[stem] = (0.30, 0.28, 0.10, 0.0)
rgba[..., 3] = (blade | stem).astype(np.float32)
image = bpy.data.images.new("leaf", size, size, alpha=True)
image.pixels.foreach_set(rgba.ravel())
image.file_format = "PNG"
image.pack()

bpy.ops.mesh.primitive_plane_add(size=1.0)
leaf = bpy.context.active_object
leaf.name = "leaf"
material = bpy.data.materials.new("leaf")
material.use_nodes = True
material.blend_method = "CLIP"
material.alpha_threshold = 0.5
nodes, links = material.node_tree.nodes, material.node_tree.links
bsdf = nodes["Principled BSDF"]
bsdf.inputs["Roughness"].default_value = 0.6
texture = nodes.new("ShaderNodeTexImage")
texture.image = image
links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
links.new(texture.outputs["Alpha"], bsdf.inputs["Alpha"])
leaf.data.materials.append(material)

bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_apply=True)
