#!/usr/bin/env bash
# Renders the README gallery: every scene of assets/scenes/ at 960x540 with 128 cells and 256^2
# shadow tiles, to screenshots/gallery/<scene>.png (plus the viewer under Xvfb when available).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
envshadow="${ENVSHADOW_BUILD_DIR:-$root/build}/app/envshadow"
[ -x "$envshadow" ] || scripts/build.sh
mkdir -p screenshots/gallery
for scene in assets/scenes/*.json; do
  name="$(basename "$scene" .json)"
  time="0"
  [ "$name" = flyover ] && time="1.5"
  "$envshadow" render --scene "$scene" --width 960 --height 540 --lights 128 --tile 256 --time "$time" \
    --out "screenshots/gallery/$name.png" | sed "s/^/$name: /"
done
# The glossy spheres again with the paper's method (--shading cells --shadows hard): a dot per cell.
"$envshadow" render --scene assets/scenes/spheres.json --width 960 --height 540 --lights 128 --tile 256 \
  --shading cells --shadows hard --out screenshots/gallery/spheres_cells.png | sed "s/^/spheres_cells: /"
# glTF's BRDF against the Phong stand-in that cells shading draws (gold reflects grey there).
"$envshadow" render --scene assets/scenes/metal_roughness.json --width 960 --height 540 --lights 128 --tile 256 \
  --shading cells --out screenshots/gallery/metal_roughness_cells.png | sed "s/^/metal_roughness_cells: /"
# A bare glTF box under courtyard with N = 64: each cell's hard edge (a fan of 64 copies) against its
# penumbra from the cell's cap (--shadows soft, docs/DESIGN.md §5.9).
box=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
if [ -f "$box" ]; then
  for shadows in hard soft; do
    "$envshadow" render --scene "$box" --width 960 --height 540 --lights 64 --tile 256 --shadows "$shadows" \
      --out "screenshots/gallery/box_shadows_$shadows.png" | sed "s/^/box_shadows_$shadows: /"
  done
fi
# The half rate's fraction where the sun's shadows are thinner than two pixels: the window frame's lines at
# 480x270, with the sun's shadow taken from the fraction's texels and looked up per pixel (docs/DESIGN.md §5.14).
for sun in off on; do
  "$envshadow" render --scene assets/scenes/glass_pane.json --width 480 --height 270 --lights 128 --tile 256 \
    --sun-per-pixel "$sun" --out "screenshots/gallery/glass_pane_sun_$sun.png" | sed "s/^/glass_pane_sun_$sun: /"
done
# glTF animation: animated.json at four times side by side (the skin bending, the cube morphing, their
# shadows following).
frames=()
for t in 0 1 2 3; do
  "$envshadow" render --scene assets/scenes/animated.json --width 320 --height 240 --lights 128 --tile 256 \
    --time "$t" --out "screenshots/gallery/.animated_$t.png" >/dev/null
  frames+=("screenshots/gallery/.animated_$t.png")
done
scripts/png-strip.py screenshots/gallery/animated_strip.png "${frames[@]}"
rm -f "${frames[@]}"
if command -v xvfb-run >/dev/null; then
  xvfb-run -a -s '-screen 0 1600x900x24' "$envshadow" view --scene assets/scenes/default.json --lights 64 \
    --width 1600 --height 900 --frames 20 --screenshot screenshots/gallery/viewer.png
fi
# The leaf cards' truth beside them (envshadow reference: about 3 minutes on 2 cores).
"$envshadow" reference --scene assets/scenes/leaves.json --width 480 --height 270 --error 0.03 \
  --exr "$(mktemp -d)/leaves_reference.exr" --png screenshots/gallery/leaves_reference.png | sed "s/^/leaves_reference: /"
# glTF content through Blender's Cycles beside them (scripts/cycles-sphere.py; about 2 minutes each on 2 cores).
if command -v blender >/dev/null; then
  for name in metal_roughness gold_sphere roughness_bands normal_panel emissive_sphere leaves glass_pane; do
    exposure=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["environment"].get("exposure", 0))' \
      "assets/scenes/$name.json")
    exr="$(mktemp -d)/$name.exr"
    blender -b --factory-startup --python scripts/cycles-sphere.py -- render "assets/scenes/$name.json" "$exr" \
      --width 480 --height 270 --samples 1024 --threads 2 >/dev/null
    blender -b --factory-startup --python scripts/cycles-sphere.py -- png "$exr" \
      "screenshots/gallery/${name}_cycles.png" --exposure "$exposure" >/dev/null
    echo "${name}_cycles: written"
  done
fi
