#!/usr/bin/env bash
# Installs every Debian package envshadow needs to build, test and demo, plus the real test data
# (blender-data's HDR photographs, assimp-testmodels' glTF files). Idempotent; quiet when all is present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libglfw3-dev libglm-dev libegl-dev libegl1-mesa-dev libosmesa6-dev libgl1-mesa-dri libgles-dev libopengl-dev
  python3-glad
  libopenexr-dev libtinygltf-dev libimgui-dev nlohmann-json3-dev libstb-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev libembree-dev libtbb-dev libmeshoptimizer-dev
  xvfb xauth
  gnuplot-nox
  clang-14 libclang-rt-14-dev clang-format-14 clang-format
  blender-data assimp-testmodels
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
if ! { $sudo apt-get update -qq && $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"; } >"$log" 2>&1; then
  cat "$log" >&2
  echo "install-deps: apt-get failed" >&2
  exit 1
fi
