#!/usr/bin/env bash
# Renders a fixed matrix of scenes x settings to EXR, so that two builds can be compared image by image
# with scripts/compare-matrix.sh: a change that must not move any image shows rel_rmse=0 everywhere.
#   scripts/render-matrix.sh OUTDIR [ENVSHADOW]
# The matrix: every scene of the regression set (tests/regression/render_flags.txt) at its defaults; the
# default and spheres scenes under every value of every render setting, and under the combinations that
# reach the shader variants single flags miss; the accuracy scenes (docs/accuracy/scenes) under both
# shading modes at one sample per pixel, alone and with --prepass off or --diffuse cap.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
out="${1:?usage: scripts/render-matrix.sh OUTDIR [ENVSHADOW]}"
envshadow="${2:-${ENVSHADOW_BUILD_DIR:-$root/build}/app/envshadow}"
mkdir -p "$out"
read -r -a regression < tests/regression/render_flags.txt

render() {  # NAME FLAGS...
  local name="$1"; shift
  "$envshadow" render "$@" --backend egl --exr "$out/$name.exr" >/dev/null
  echo "$name"
}

for scene in assets/scenes/*.json; do
  render "$(basename "$scene" .json)" --scene "$scene" "${regression[@]}"
done

variants=(
  "--pcf wide" "--specular single" "--cap solid-angle" "--diffuse cap" "--shading ratio" "--shadows soft"
  "--shading ratio --shadows soft" "--msaa 1" "--msaa 8" "--atlas viewport-array" "--atlas per-tile"
  "--tile-sizes uniform" "--tile-sizes sqrt" "--depth-bits 32" "--baseline" "--caster-lod off"
  "--prepass off" "--no-background" "--hemisphere full" "--method fs-gpu" "--method ccvt"
  # shader variants the single flags above do not reach
  "--prepass off --shading ratio" "--prepass off --shading ratio --shadows soft" "--prepass off --shadows soft"
  "--prepass off --pcf wide" "--prepass off --diffuse cap" "--prepass off --diffuse cap --shading ratio --specular single"
  "--diffuse cap --shading ratio" "--specular single --shading ratio" "--pcf wide --shading ratio"
  "--pcf wide --shadows soft" "--baseline --shading ratio" "--baseline --diffuse cap"
  "--baseline --shading ratio --shadows soft"
)
for scene in default spheres; do
  for variant in "${variants[@]}"; do
    read -r -a flags <<< "$variant"
    tag="$(echo "$variant" | tr -d '-' | tr ' ' '_')"
    render "${scene}__${tag}" --scene "assets/scenes/$scene.json" "${regression[@]}" "${flags[@]}"
  done
done

for scene in docs/accuracy/scenes/*.json; do
  name="$(basename "$scene" .json)"
  case "$name" in *_mask) continue ;; esac
  for shading in cells ratio; do
    for extra in "" "--prepass off" "--diffuse cap"; do
      read -r -a flags <<< "$extra"
      tag="$(echo "$extra" | tr -d '-' | tr ' ' '_')"
      render "accuracy_${name}__${shading}${tag:+__$tag}" --scene "$scene" --width 128 --height 96 --lights 32 \
        --msaa 1 --shading "$shading" "${flags[@]}"
    done
  done
done
