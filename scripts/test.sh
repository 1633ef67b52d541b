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
  # Leaks count, except those Mesa's drivers keep until exit (docs/ROBUSTNESS.md explains the file).
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
  export LSAN_OPTIONS="suppressions=$root/tests/robustness/lsan_mesa.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
else
  scripts/build.sh -DENVSHADOW_WERROR=ON
fi
cd "${ENVSHADOW_BUILD_DIR:-$root/build}"
ctest -j"$(nproc)" --output-on-failure --label-exclude 'fuzz|slow'
