#!/usr/bin/env bash
# `envshadow reference` against Blender's Cycles on unshadowed spheres (docs/accuracy/cycles_by_hand.md).
#   scripts/cycles-compare.sh [OUT_DIR]
# Environment: ENVSHADOW (binary, default build/app/envshadow), MAPS (names under Blender's
# studiolights/world), CASES (a subset of the names below), SIZE (96), SAMPLES (Cycles' most per pixel,
# 2048), ERROR (reference's --error, 0.0025), THREADS (Cycles, 2). Needs blender (Debian's 3.4).
# Prints one row per map and case, then the diffuse decomposition where lambert, white_diel and black_diel
# all ran. rel_rmse: `envshadow compare` (alpha > 0.5); interior: the same without the silhouette ring;
# r g b lum: mean ratio Cycles/reference over the sphere; bg_ratio: the same over the background.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-/tmp/cycles-compare}
bin=${ENVSHADOW:-$here/../build/app/envshadow}
maps=${MAPS:-"studio city"}
size=${SIZE:-96}
samples=${SAMPLES:-2048}
err=${ERROR:-0.0025}
threads=${THREADS:-2}
mapdir=/usr/share/blender/datafiles/studiolights/world
mkdir -p "$out"

declare -A mat=(
  [mirror]='{"base_color": 1, "metallic": 1, "roughness": 0.05}'
  [white_diel]='{"base_color": 1, "metallic": 0, "roughness": 0.5}'
  [red_diel]='{"base_color": [0.8, 0.2, 0.1], "metallic": 0, "roughness": 0.5}'
  [gold]='{"base_color": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.4}'
  [rough_metal]='{"base_color": 0.9, "metallic": 1, "roughness": 0.8}'
  [smooth_metal]='{"base_color": 0.9, "metallic": 1, "roughness": 0.2}'
  [white_metal]='{"base_color": 1, "metallic": 1, "roughness": 0.5}'
  [black_diel]='{"base_color": 0, "metallic": 0, "roughness": 0.5}'
  [lambert]='{"diffuse": 1}'
)
cases=${CASES:-"mirror white_diel red_diel gold rough_metal smooth_metal white_metal black_diel lambert"}

printf '%-8s %-13s %9s %9s %7s %7s %7s %7s %8s %6s %6s\n' map case rel_rmse interior r g b lum bg_ratio ref_s cyc_s
for m in $maps; do
  for c in $cases; do
    d=$out/$m/$c
    mkdir -p "$d"
    cat >"$d/scene.json" <<EOF
{
  "description": "Cycles check: one sphere, no ground, $m map, case $c.",
  "environment": {"source": "$mapdir/$m.exr", "rotation": 0, "exposure": 0},
  "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "fov": 40},
  "objects": [{"name": "sphere", "mesh": {"type": "sphere", "radius": 0.8, "segments": 256},
               "material": ${mat[$c]}}]
}
EOF
    t0=$(date +%s.%N)
    "$bin" reference --scene "$d/scene.json" --width "$size" --height "$size" --error "$err" \
      --exr "$d/ref.exr" --png "$d/ref.png" >"$d/ref.log" 2>&1
    t1=$(date +%s.%N)
    blender -b --factory-startup --python "$here/cycles-sphere.py" -- render "$d/scene.json" "$d/cycles.exr" \
      --width "$size" --height "$size" --samples "$samples" --threads "$threads" >"$d/cycles.log" 2>&1
    t2=$(date +%s.%N)
    "$bin" compare "$d/ref.exr" "$d/cycles.exr" --diff "$d/diff.png" >"$d/compare.txt"
    blender -b --factory-startup --python "$here/cycles-sphere.py" -- stats "$d/ref.exr" "$d/cycles.exr" \
      --png "$d/side.png" 2>&1 | grep '^pixels' >"$d/stats.txt"
    python3 - "$d" "$m" "$c" "$t0" "$t1" "$t2" <<'EOF'
import sys
d, m, c, t0, t1, t2 = sys.argv[1:]
cmp = dict(kv.split("=") for kv in open(f"{d}/compare.txt").read().split())
s = open(f"{d}/stats.txt").read().split()
st = dict(zip(s[::2], s[1::2]))
print(f"{m:<8} {c:<13} {float(cmp['rel_rmse'])*100:8.2f}% {float(st['rel_rmse_interior'])*100:8.2f}% "
      f"{st['ratio_r']:>7} {st['ratio_g']:>7} "
      f"{st['ratio_b']:>7} {st['ratio_lum']:>7} {st['bg_ratio']:>8} {float(t1)-float(t0):6.1f} "
      f"{float(t2)-float(t1):6.1f}")
EOF
  done
done

# Diffuse decomposition: diffuse = white_diel - black_diel (the BRDF is linear in baseColor at metallic 0),
# each renderer's diffuse over its own Lambert sphere (same sphere pixels: the reference's alpha).
for m in $maps; do
  [[ -f $out/$m/lambert/cycles.exr && -f $out/$m/white_diel/cycles.exr && -f $out/$m/black_diel/cycles.exr ]] || continue
  blender -b --factory-startup --python "$here/cycles-sphere.py" -- decompose \
    "$out/$m/lambert" "$out/$m/white_diel" "$out/$m/black_diel" 2>&1 | grep '^diffuse' | sed "s/^/$m /"
done
