#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the default scene: the interactive
# viewer when a display exists, else an offscreen render to screenshots/demo.png with its timings.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/install-deps.sh
scripts/build.sh
envshadow="${ENVSHADOW_BUILD_DIR:-$root/build}/app/envshadow"
scene="$root/assets/scenes/default.json"

if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && "$envshadow" view --help >/dev/null 2>&1 && [ -f "$scene" ]; then
  exec "$envshadow" view --scene "$scene"
fi
mkdir -p screenshots
if [ -f "$scene" ]; then
  "$envshadow" render --scene "$scene" --out screenshots/demo.png
else
  "$envshadow" render --out screenshots/demo.png
fi
echo "demo: wrote screenshots/demo.png"
