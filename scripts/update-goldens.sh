#!/usr/bin/env bash
# Regenerates screenshots/golden/ — the images the regression suite (ctest -L regression) compares
# against — with the flags in tests/regression/render_flags.txt. Run it only when the look changed
# on purpose, then open every image before committing it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
envshadow="${ENVSHADOW_BUILD_DIR:-$root/build}/app/envshadow"
[ -x "$envshadow" ] || scripts/build.sh
read -r -a flags < tests/regression/render_flags.txt
mkdir -p screenshots/golden
for scene in assets/scenes/*.json; do
  name="$(basename "$scene" .json)"
  "$envshadow" render --scene "$scene" "${flags[@]}" --backend egl --out "screenshots/golden/$name.png" >/dev/null
  echo "screenshots/golden/$name.png"
done
