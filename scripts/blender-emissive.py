"""An emissive object, as users bring them: Blender's Principled BSDF with an Emission colour and a strength
above 1, written by Blender's own glTF exporter as emissiveFactor and KHR_materials_emissive_strength. A sphere
of radius 0.25 m (64 segments by 32 rings, smooth), a dark grey dielectric of roughness 0.5 glowing orange.

    blender -b --factory-startup --python scripts/blender-emissive.py -- assets/models/emissive_sphere.glb
"""
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)

bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=0.25)
sphere = bpy.context.active_object
sphere.name = "emissive sphere"
bpy.ops.object.shade_smooth()
material = bpy.data.materials.new("glowing orange")
material.use_nodes = True
bsdf = material.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.1, 0.1, 0.1, 1.0)
bsdf.inputs["Roughness"].default_value = 0.5
bsdf.inputs["Metallic"].default_value = 0.0
bsdf.inputs["Emission"].default_value = (1.0, 0.45, 0.1, 1.0)
bsdf.inputs["Emission Strength"].default_value = 2.0
sphere.data.materials.append(material)

bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_apply=True)
