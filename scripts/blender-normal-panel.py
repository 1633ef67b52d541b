"""A flat panel whose relief is all in its normal map, as users bring them: Blender's Principled BSDF with a
Non-Color image through a Normal Map node (tangent space), written by Blender's own glTF exporter as a
normalTexture with the mesh's MikkTSpace tangents (TANGENT). The map (256 x 256) holds a 4 x 4 grid of
smooth domes, their slopes up to 50 degrees, on a flat field; the panel is 1 m square, light grey,
roughness 0.4, a dielectric.

    blender -b --factory-startup --python scripts/blender-normal-panel.py -- assets/models/normal_panel.glb
"""
import sys

import bpy
import numpy as np

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)

size, domes = 256, 4
cell = size / domes
# Texel centres in cell units, about each dome's centre; Blender's rows run bottom to top, as +y of a
# tangent-space normal map does (OpenGL's and glTF's convention).
coords = (np.arange(size) + 0.5) / cell
local = coords - np.floor(coords) - 0.5
x, y = np.meshgrid(local, local)  # x along the columns (u), y along the rows (v, up the image)
# Each dome's height h = A (1 - r^2/R^2)^2 (cell units) for r < R: smooth to its rim, where the map meets the
# flat field without a step; A = 0.775 R makes its steepest slope, at r = R / sqrt(3), 50 degrees.
radius = 0.4
height = 0.775 * radius
r2 = x * x + y * y
inside = r2 < radius * radius
fall = np.where(inside, 1.0 - r2 / (radius * radius), 0.0)
dh_dx = -4.0 * height * fall * x / (radius * radius)  # dh/dr (x / r)
dh_dy = -4.0 * height * fall * y / (radius * radius)
normal = np.stack([-dh_dx, -dh_dy, np.ones_like(x)], axis=-1)
normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
rgba = np.ones((size, size, 4), np.float32)
rgba[..., :3] = 0.5 * normal + 0.5
image = bpy.data.images.new("domes", size, size, alpha=True)
image.colorspace_settings.name = "Non-Color"
image.pixels.foreach_set(rgba.ravel())
image.file_format = "PNG"
image.pack()

bpy.ops.mesh.primitive_plane_add(size=1.0)
panel = bpy.context.active_object
panel.name = "normal panel"
material = bpy.data.materials.new("domed grey")
material.use_nodes = True
nodes, links = material.node_tree.nodes, material.node_tree.links
bsdf = nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.7, 0.7, 0.7, 1.0)
bsdf.inputs["Roughness"].default_value = 0.4
bsdf.inputs["Metallic"].default_value = 0.0
texture = nodes.new("ShaderNodeTexImage")
texture.image = image
normal_map = nodes.new("ShaderNodeNormalMap")
normal_map.space = "TANGENT"
links.new(texture.outputs["Color"], normal_map.inputs["Color"])
links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
panel.data.materials.append(material)

bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_apply=True, export_tangents=True)
