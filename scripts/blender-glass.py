"""A window pane as users bring them: a 1 m square plane whose base-colour texture's alpha is 1 on a lead
frame and a cross of mullions and 0.3 on four pale glass panes, its material set to Alpha Blend, written by
Blender's own glTF exporter (alphaMode BLEND). The plane stands upright: turned 90 degrees about X it faces -Y
in Blender, which is +Z in glTF's frame (the exporter turns Blender's Z up into glTF's Y up).

    blender -b --python scripts/blender-glass.py -- assets/models/glass_pane.glb
"""
import math
import sys

import bpy
import numpy as np

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)

size = 256
v, u = (np.mgrid[0:size, 0:size] + 0.5) / size
frame = (np.minimum(np.minimum(u, 1.0 - u), np.minimum(v, 1.0 - v)) < 0.06) | (np.abs(u - 0.5) < 0.025) | (
    np.abs(v - 0.5) < 0.025)
rgba = np.zeros((size, size, 4), np.float32)
rgba[...] = (0.75, 0.85, 0.95, 0.3)  # the glass
rgba[frame] = (0.08, 0.08, 0.09, 1.0)  # the lead
image = bpy.data.images.new("glass", size, size, alpha=True)
image.pixels.foreach_set(rgba.ravel())
image.file_format = "PNG"
image.pack()

bpy.ops.mesh.primitive_plane_add(size=1.0, rotation=(math.pi / 2, 0.0, 0.0))
pane = bpy.context.active_object
pane.name = "glass_pane"
material = bpy.data.materials.new("glass")
material.use_nodes = True
material.blend_method = "BLEND"
nodes, links = material.node_tree.nodes, material.node_tree.links
bsdf = nodes["Principled BSDF"]
bsdf.inputs["Roughness"].default_value = 0.3
texture = nodes.new("ShaderNodeTexImage")
texture.image = image
links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
links.new(texture.outputs["Alpha"], bsdf.inputs["Alpha"])
pane.data.materials.append(material)

bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_apply=True)
