# Renders an envshadow scene (spheres, planes, glTF models) under its environment with Blender's Cycles,
# direct light only, as an independent check of `envshadow reference` (docs/accuracy/cycles_by_hand.md).
#
#   blender -b --factory-startup --python scripts/cycles-sphere.py -- render SCENE.json OUT.exr \
#       [--width 96] [--height 96] [--samples 2048] [--threads 2] [--seed 0]
#   blender -b --factory-startup --python scripts/cycles-sphere.py -- stats REF.exr CYCLES.exr [--png SIDE.png]
#   blender -b --factory-startup --python scripts/cycles-sphere.py -- decompose LAMBERT_DIR WHITE_DIR BLACK_DIR
#   blender -b --factory-startup --python scripts/cycles-sphere.py -- png IN.exr OUT.png [--exposure 0]
#   blender -b --factory-startup --python scripts/cycles-sphere.py -- mask REF.exr OUT.png
#
# `render` reads the envshadow scene file itself (camera, environment, objects), so both renderers see
# the same numbers. Supported: a map file or builtin:constant[:R]; objects of mesh type sphere (radius,
# segments) or plane (size; a "ground" plane is made 2 km wide, so that it acts as infinite as envshadow's
# ground does: docs/SCENES.md), and glTF models (Blender's own importer, its materials as it maps them:
# alpha MASK included), each with a transform (translation, rotation as Euler angles or axis and angle,
# scale; no "fit"); materials with base_color/metallic/roughness (Principled BSDF, GGX, specular 0.5 =
# F0 0.04) or a pure Lambert {"diffuse": d} (Diffuse BSDF, roughness 0).
# `stats` prints per-channel mean ratios CYCLES/REF over REF's object pixels (alpha > 0.5) and the
# relative difference of the background; --png writes REF | CYCLES | relative difference (red = 10%).
# `png` tone-maps an EXR as `envshadow render --out` does (ACES); `mask` writes REF's object pixels as the
# white-on-black PNG `envshadow compare --mask` takes. `decompose` takes three case folders (ref.exr, cycles.exr in each) and splits the white dielectric into
# diffuse (white - black base colour: the BRDF is linear in it) and specular, each against Lambert.
#
# Conventions (docs/DESIGN.md §2):
# - envshadow world (x, y, z), +Y up  ->  Blender (x, -z, y), +Z up (a proper rotation).
# - envshadow lat-long: phi = atan2(z, x) = 2 pi u, theta = acos(y) = pi v, row 0 at the zenith.
#   Cycles' equirectangular lookup of a Blender direction d: u = 0.5 - atan2(d.y, d.x) / (2 pi),
#   zenith at the image top. With d = (x, -z, y), atan2(d.y, d.x) = -phi, so Cycles reads u + 0.5:
#   the lookup vector is turned by pi about +Z. The scene's environment.rotation (world = R_y(rot) map,
#   right-handed) is R_z(rot) in Blender, so the texture's vector is R_z(pi - rot) d (Mapping node, POINT).
#   Verified on the background pixels and a roughness-0.05 metal sphere (rotations 0 and 90).
# - The map is read with Closest interpolation: envshadow treats texels as constant.
import json
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Matrix, Vector

# Debian 12's Blender 3.4 glTF importer still writes np.bool, which Debian's numpy 1.24 removed.
if not hasattr(np, "bool"):
    np.bool = bool


def to_blender(p):
    return Vector((p[0], -p[2], p[1]))


# envshadow's world to Blender's: (x, y, z) -> (x, -z, y).
TO_BLENDER = Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))


def transform_matrix(t):
    """An envshadow transform (docs/SCENES.md `transform`) as a Blender matrix: C T C^-1."""
    translation = Matrix.Translation(Vector(t.get("translation", [0, 0, 0])))
    r = t.get("rotation")
    rotation = Matrix.Identity(4)
    if isinstance(r, dict):
        rotation = Matrix.Rotation(math.radians(r["angle"]), 4, Vector(r["axis"]).normalized())
    elif r is not None:  # fixed axes, X first, then Y, then Z
        for angle, axis in zip(r, "XYZ"):
            rotation = Matrix.Rotation(math.radians(angle), 4, axis) @ rotation
    sc = t.get("scale", 1.0)
    sc = [sc] * 3 if isinstance(sc, (int, float)) else sc
    scale = Matrix.Diagonal(Vector((*sc, 1.0)))
    return TO_BLENDER @ translation @ rotation @ scale @ TO_BLENDER.inverted()


def parse(argv, flags):
    pos, opts = [], {}
    i = 0
    while i < len(argv):
        if argv[i].startswith("--"):
            opts[argv[i][2:]] = argv[i + 1]
            i += 2
        else:
            pos.append(argv[i])
            i += 1
    for k in opts:
        if k not in flags:
            sys.exit(f"cycles-sphere.py: unknown option --{k}")
    return pos, opts


def build_world(scene_dir, env):
    if isinstance(env, str):
        env = {"source": env}
    src = env.get("source", "builtin:sky")
    rot = math.radians(env.get("rotation", 0.0))
    world = bpy.data.worlds.new("env")
    world.use_nodes = True
    nt = world.node_tree
    bg = nt.nodes["Background"]
    bg.inputs["Strength"].default_value = 1.0
    if src.startswith("builtin:constant"):
        v = float(src.split(":")[2]) if src.count(":") == 2 else 1.0
        bg.inputs["Color"].default_value = (v, v, v, 1.0)
        world.cycles.sampling_method = "NONE"
    elif src.startswith("builtin:"):
        sys.exit(f"cycles-sphere.py: {src} is not supported")
    else:
        path = src if os.path.isabs(src) else os.path.join(scene_dir, src)
        img = bpy.data.images.load(path)
        img.colorspace_settings.name = "Linear"
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = img
        tex.interpolation = "Closest"
        tex.projection = "EQUIRECTANGULAR"
        coord = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.pi - rot)
        nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
        world.cycles.sampling_method = "MANUAL"
        world.cycles.sample_map_resolution = img.size[0]
    return world


def build_material(m):
    mat = bpy.data.materials.new("sphere")
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    gltf = {"base_color", "metallic", "roughness"}
    if set(m) <= gltf and m:
        bc = m.get("base_color", 1.0)
        bc = [bc] * 3 if isinstance(bc, (int, float)) else bc
        p = nt.nodes.new("ShaderNodeBsdfPrincipled")
        p.distribution = "GGX"
        p.inputs["Base Color"].default_value = (*bc, 1.0)
        p.inputs["Metallic"].default_value = m.get("metallic", 1.0)
        p.inputs["Roughness"].default_value = m.get("roughness", 1.0)
        p.inputs["Specular"].default_value = 0.5
        p.inputs["Specular Tint"].default_value = 0.0
        p.inputs["Sheen"].default_value = 0.0
        p.inputs["Clearcoat"].default_value = 0.0
        p.inputs["Subsurface"].default_value = 0.0
        p.inputs["Transmission"].default_value = 0.0
        p.inputs["Emission"].default_value = (0.0, 0.0, 0.0, 1.0)
        nt.links.new(p.outputs["BSDF"], out.inputs["Surface"])
    elif set(m) == {"diffuse"}:
        d = m["diffuse"]
        d = [d] * 3 if isinstance(d, (int, float)) else d
        p = nt.nodes.new("ShaderNodeBsdfDiffuse")
        p.inputs["Color"].default_value = (*d, 1.0)
        p.inputs["Roughness"].default_value = 0.0  # Lambert
        nt.links.new(p.outputs["BSDF"], out.inputs["Surface"])
    else:
        sys.exit(f"cycles-sphere.py: material {m} is not supported (glTF keys, or diffuse alone)")
    return mat


def clip_alpha(mat):
    """glTF's alpha MASK in Cycles: Blender's importer sets the clip threshold for Eevee alone (Cycles
    reads the alpha as a fraction), so the Principled BSDF's alpha is put through alpha > cutoff here."""
    if mat.blend_method != "CLIP" or not mat.use_nodes:
        return
    nt = mat.node_tree
    for node in nt.nodes:
        if node.type != "BSDF_PRINCIPLED":
            continue
        alpha = node.inputs["Alpha"]
        clip = nt.nodes.new("ShaderNodeMath")
        clip.operation = "GREATER_THAN"
        clip.inputs[1].default_value = mat.alpha_threshold
        if alpha.is_linked:
            nt.links.new(alpha.links[0].from_socket, clip.inputs[0])
        else:
            clip.inputs[0].default_value = alpha.default_value
        nt.links.new(clip.outputs[0], alpha)


def render(argv):
    pos, o = parse(argv, {"width", "height", "samples", "threads", "seed"})
    scene_path, out_path = pos
    desc = json.load(open(scene_path))
    scene_dir = os.path.dirname(os.path.abspath(scene_path))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.world = build_world(scene_dir, desc.get("environment", "builtin:sky"))

    for obj in desc["objects"]:
        if "fit" in obj:
            sys.exit("cycles-sphere.py: \"fit\" is not supported")
        placement = transform_matrix(obj.get("transform", {}))
        if "model" in obj:
            path = obj["model"] if os.path.isabs(obj["model"]) else os.path.join(scene_dir, obj["model"])
            before = set(bpy.data.objects)
            bpy.ops.import_scene.gltf(filepath=path)
            if "material" in obj:
                sys.exit("cycles-sphere.py: a model's material override is not supported")
            for imported in set(bpy.data.objects) - before:
                if imported.parent is None:
                    imported.matrix_world = placement @ imported.matrix_world
                for slot in imported.material_slots:
                    if slot.material is not None:
                        clip_alpha(slot.material)
            continue
        mesh = obj["mesh"]
        mesh = {"type": mesh} if isinstance(mesh, str) else mesh
        if mesh["type"] == "sphere":
            seg = int(mesh.get("segments", 64))
            bpy.ops.mesh.primitive_uv_sphere_add(segments=seg, ring_count=seg // 2, radius=mesh.get("radius", 0.5))
            bpy.ops.object.shade_smooth()
        elif mesh["type"] == "plane":
            size = 2000.0 if obj.get("ground") else float(mesh.get("size", 1.0))
            bpy.ops.mesh.primitive_plane_add(size=size)  # in Blender's XY plane: envshadow's XZ, facing +Y
        else:
            sys.exit(f"cycles-sphere.py: mesh type {mesh['type']} is not supported")
        s = bpy.context.active_object
        s.matrix_world = placement @ s.matrix_world
        s.data.materials.append(build_material(obj.get("material", {"diffuse": 0.8})))

    cam = desc["camera"]
    cd = bpy.data.cameras.new("cam")
    cd.sensor_fit = "VERTICAL"
    cd.angle_y = math.radians(cam.get("fov", 45.0))
    cd.clip_start, cd.clip_end = 0.01, 1000.0
    co = bpy.data.objects.new("cam", cd)
    sc.collection.objects.link(co)
    eye, target = to_blender(cam["position"]), to_blender(cam["target"])
    up = cam.get("up", [0, 1, 0])
    if list(up) != [0, 1, 0]:
        sys.exit("cycles-sphere.py: only camera up +Y is supported")
    co.location = eye
    co.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
    sc.camera = co

    r = sc.render
    r.engine = "CYCLES"
    r.resolution_x = int(o.get("width", 96))
    r.resolution_y = int(o.get("height", 96))
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.threads_mode = "FIXED"
    r.threads = int(o.get("threads", 2))
    r.use_persistent_data = False
    c = sc.cycles
    c.device = "CPU"
    c.samples = int(o.get("samples", 2048))
    c.use_adaptive_sampling = True
    c.adaptive_threshold = 0.001
    c.adaptive_min_samples = 64
    c.use_denoising = False
    c.seed = int(o.get("seed", 0))
    # Direct light only: the camera ray's hit is lit by the world (light sampling and BSDF rays that
    # reach the background, MIS), and nothing bounces further.
    c.max_bounces = 0
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 0
    c.volume_bounces = 0
    c.transparent_max_bounces = 16  # through alpha-masked cut-outs (not a bounce of light)
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.caustics_reflective = c.caustics_refractive = False
    c.blur_glossy = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    vs = sc.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    sc.sequencer_colorspace_settings.name = "Linear"
    im = r.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGBA"
    im.color_depth = "32"
    im.exr_codec = "ZIP"
    r.filepath = os.path.abspath(out_path)
    r.use_file_extension = False
    bpy.ops.render.render(write_still=True)


def load(path):
    img = bpy.data.images.load(os.path.abspath(path))
    img.colorspace_settings.name = "Non-Color"
    w, h = img.size
    a = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(a)
    return a.reshape(h, w, 4)  # bottom row first, as Blender stores it


def srgb8(x):
    x = np.clip(x, 0.0, 1.0)
    y = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return y


def stats(argv):
    pos, o = parse(argv, {"png"})
    ref, cyc = load(pos[0]), load(pos[1])
    mask = ref[..., 3] > 0.5
    bgm = ref[..., 3] == 0.0
    lum = np.array([0.2126, 0.7152, 0.0722])
    rs, cs = ref[mask][:, :3], cyc[mask][:, :3]
    ratio = cs.sum(0) / rs.sum(0)
    lr = (cs @ lum).sum() / (rs @ lum).sum()
    rl = rs @ lum
    rel = np.sqrt(np.mean(((cs - rs) @ lum) ** 2) / np.mean(rl ** 2))
    # interior: full coverage here and at the 8 neighbours (drops the silhouette ring)
    full = ref[..., 3] >= 1.0
    inner = full.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner &= np.roll(np.roll(full, dy, 0), dx, 1)
    ri, ci = ref[inner][:, :3], cyc[inner][:, :3]
    rel_in = np.sqrt(((ci - ri) ** 2).sum() / (ri ** 2).sum())
    rb, cb = ref[bgm][:, :3], cyc[bgm][:, :3]
    bg = np.abs(cb - rb).sum() / max(np.abs(rb).sum(), 1e-30)
    bg_ratio = cb.sum() / max(rb.sum(), 1e-30)
    print(f"pixels {mask.sum()} ratio_r {ratio[0]:.4f} ratio_g {ratio[1]:.4f} ratio_b {ratio[2]:.4f} "
          f"ratio_lum {lr:.4f} rel_rmse_lum {rel:.4f} interior_pixels {inner.sum()} "
          f"rel_rmse_interior {rel_in:.4f} bg_pixels {bgm.sum()} bg_ratio {bg_ratio:.4f} "
          f"bg_mean_abs_rel {bg:.4f}")
    if "png" in o:
        scale = 1.0 / max(np.percentile(rl, 99), 1e-6) * 0.8  # the same exposure for both halves
        def tm(x):
            return srgb8(x[..., :3] * scale)
        d = np.abs(cyc[..., :3] @ lum - ref[..., :3] @ lum) / np.maximum(ref[..., :3] @ lum, 1e-6)
        d = np.where(mask, np.clip(d / 0.1, 0, 1), 0)
        diff = np.stack([d, np.zeros_like(d), np.zeros_like(d)], -1)
        h, w = mask.shape
        side = np.concatenate([tm(ref), np.ones((h, 2, 3)), tm(cyc), np.ones((h, 2, 3)), diff], 1)
        side = np.repeat(np.repeat(side, 3, 0), 3, 1)  # nearest, x3, to be seen
        save_png(side, o["png"])


def png(argv):
    """EXR -> PNG as `envshadow render --out` writes one: times 2^exposure, ACES (Narkowicz 2015, per
    channel, as engine/core/tonemap.cpp), sRGB-encoded."""
    pos, o = parse(argv, {"exposure"})
    img = load(pos[0])
    x = img[..., :3] * 2.0 ** float(o.get("exposure", 0.0))
    a, b, c, d, e = 2.51, 0.03, 2.43, 0.59, 0.14
    y = np.clip((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0)
    save_png(srgb8(y), pos[1])


def mask(argv):
    """The pixels REF.exr's alpha marks (> 0.5) as a white-on-black PNG, for `envshadow compare --mask`."""
    ref = load(argv[0])
    m = (ref[..., 3] > 0.5).astype(np.float32)
    save_png(np.stack([m, m, m], -1), argv[1])


def save_png(rgb, path):
    """RGB in 0..1, bottom row first (Blender's order), to an 8-bit PNG as stored (no colour transform)."""
    h, w = rgb.shape[:2]
    out = bpy.data.images.new("png", w, h, alpha=True)
    out.colorspace_settings.name = "Non-Color"
    px = np.concatenate([rgb, np.ones((h, w, 1))], -1).astype(np.float32)
    out.pixels.foreach_set(px.ravel())
    out.filepath_raw = os.path.abspath(path)
    out.file_format = "PNG"
    out.save()


def decompose(argv):
    lam, white, black = argv
    L = {}
    for k, d in (("l", lam), ("w", white), ("b", black)):
        L[k + "r"], L[k + "c"] = load(f"{d}/ref.exr"), load(f"{d}/cycles.exr")
    mask = L["lr"][..., 3] > 0.5
    h, w = mask.shape
    y, x = np.mgrid[0:h, 0:w]
    rad = np.hypot(x + 0.5 - w / 2, y + 0.5 - h / 2)
    rad = rad / rad[mask].max()
    lum = np.array([0.2126, 0.7152, 0.0722])
    Y = {k: v[..., :3] @ lum for k, v in L.items()}
    parts = {"all": mask, "centre": mask & (rad < 0.5), "rim": mask & (rad > 0.8)}
    for name, m in parts.items():
        def s(k):
            return Y[k][m].sum()
        print(f"diffuse {name:<6} lambert_cyc/ref {s('lc') / s('lr'):.4f} "
              f"ref_diffuse/lambert {(s('wr') - s('br')) / s('lr'):.4f} "
              f"cyc_diffuse/lambert {(s('wc') - s('bc')) / s('lc'):.4f} "
              f"diffuse_cyc/ref {(s('wc') - s('bc')) / (s('wr') - s('br')):.4f} "
              f"spec_cyc/ref {s('bc') / s('br'):.4f} spec_share_ref {s('br') / s('wr'):.4f} "
              f"white_cyc/ref {s('wc') / s('wr'):.4f}")


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    modes = {"render": render, "stats": stats, "decompose": decompose, "png": png, "mask": mask}
    if not args or args[0] not in modes:
        sys.exit("usage: see the header of cycles-sphere.py")
    modes[args[0]](args[1:])
