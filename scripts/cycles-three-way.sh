#!/usr/bin/env bash
# One scene three ways: `envshadow render` and `envshadow reference` at their defaults, and Blender's Cycles
# (scripts/cycles-sphere.py: direct light only, the ground 2 km wide), each pair compared over the
# reference's object pixels (docs/ACCURACY.md "glTF materials three ways").
#   scripts/cycles-three-way.sh SCENE.json OUT_DIR [WIDTH HEIGHT]
# Environment: ENVSHADOW (binary, default build/app/envshadow), LIGHTS (N, 128), SAMPLES (Cycles' most per
# pixel, 1024), THREADS (Cycles, 2). Needs blender (Debian's 3.4). Writes render, reference and cycles
# .exr/.png, mask.png and the three diff PNGs into OUT_DIR; prints one line per pair.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
scene=$1
out=$2
width=${3:-192}
height=${4:-108}
bin=${ENVSHADOW:-$here/../build/app/envshadow}
lights=${LIGHTS:-128}
samples=${SAMPLES:-1024}
threads=${THREADS:-2}
mkdir -p "$out"
exposure=$(python3 -c 'import json, sys; e = json.load(open(sys.argv[1])).get("environment", {});
print(e.get("exposure", 0) if isinstance(e, dict) else 0)' "$scene")
cycles() { blender -b --factory-startup --python "$here/cycles-sphere.py" -- "$@" >>"$out/cycles.log" 2>&1; }

"$bin" render --scene "$scene" --width "$width" --height "$height" --lights "$lights" \
  --exr "$out/render.exr" --out "$out/render.png" >"$out/render.log" 2>&1
"$bin" reference --scene "$scene" --width "$width" --height "$height" \
  --exr "$out/reference.exr" --png "$out/reference.png" >"$out/reference.log" 2>&1
: >"$out/cycles.log"
cycles render "$scene" "$out/cycles.exr" --width "$width" --height "$height" --samples "$samples" --threads "$threads"
cycles png "$out/cycles.exr" "$out/cycles.png" --exposure "$exposure"
cycles mask "$out/reference.exr" "$out/mask.png"

pair() {  # label, A (the truth of the pair), B
  printf '%-22s %s\n' "$1" "$("$bin" compare "$2" "$3" --mask "$out/mask.png" --diff "$out/diff_$4.png")"
}
pair "render vs reference" "$out/reference.exr" "$out/render.exr" render_reference
pair "reference vs Cycles" "$out/cycles.exr" "$out/reference.exr" reference_cycles
pair "render vs Cycles" "$out/cycles.exr" "$out/render.exr" render_cycles
