#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, runs the whole test suite with ctest.
#   scripts/test.sh              the default suite (unit, gl, app, regression)
#   scripts/test.sh --sanitize   the same under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

sanitize=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    *) echo "usage: scripts/test.sh [--sanitize]" >&2; exit 2 ;;
  esac
done

scripts/install-deps.sh
if [ $sanitize -eq 1 ]; then
  export ENVSHADOW_BUILD_DIR="$root/build-asan"
  scripts/build.sh -DENVSHADOW_WERROR=ON -DENVSHADOW_SANITIZE=ON -DENVSHADOW_BUILD_BENCHMARKS=OFF
else
  scripts/build.sh -DENVSHADOW_WERROR=ON
fi
cd "${ENVSHADOW_BUILD_DIR:-$root/build}"
ctest -j"$(nproc)" --output-on-failure --label-exclude 'fuzz|slow'
