#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, runs the whole test suite with ctest.
#   scripts/test.sh              the default suite (ctest labels unit, gl, viewer, regression)
#   scripts/test.sh --sanitize   the same under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)
# The default suite is followed by the malformed-input tests (test_robustness: every loader on broken,
# truncated and bit-flipped files, the fuzz findings) once more under ASan + UBSan, built alone into
# build-asan-robustness/ (docs/ROBUSTNESS.md, "Sanitizers").
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
# Formatting first: it takes a second, and an unformatted file fails the run (.clang-format).
scripts/check-format.sh
# Sanitizer runs: leaks count, except those Mesa's drivers keep until exit (docs/ROBUSTNESS.md
# explains the file); the first UBSan report fails the test, with a stack. EGL and GLX unload Mesa's
# DRI driver (dlclose) before LeakSanitizer looks, so its leaks would come from "<unknown module>"
# and escape the suppressions: the driver is preloaded, which keeps it loaded to the end (and lets
# ASan come second in the library order).
sanitizer_env=(ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:verify_asan_link_order=0"
               LSAN_OPTIONS="suppressions=$root/tests/robustness/lsan_mesa.supp:print_suppressions=0"
               UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
dri_driver="/usr/lib/$(gcc -print-multiarch)/dri/swrast_dri.so"
[ -f "$dri_driver" ] && sanitizer_env+=(LD_PRELOAD="$dri_driver")
if [ $sanitize -eq 1 ]; then
  export ENVSHADOW_BUILD_DIR="$root/build-asan"
  scripts/build.sh -DENVSHADOW_WERROR=ON -DENVSHADOW_SANITIZE=ON -DENVSHADOW_BUILD_BENCHMARKS=OFF
else
  scripts/build.sh -DENVSHADOW_WERROR=ON
fi
cd "${ENVSHADOW_BUILD_DIR:-$root/build}"
if [ $sanitize -eq 1 ]; then
  env "${sanitizer_env[@]}" ctest -j"$(nproc)" --output-on-failure --label-exclude fuzz
  exit 0
fi
ctest -j"$(nproc)" --output-on-failure --label-exclude fuzz

# The malformed-input tests under ASan + UBSan: only test_robustness and what it links (core, env,
# scene; 23 files, ~280 s of CPU from clean, so 2-3 minutes on 2 cores), then its 39 tests (~15 s).
# The whole suite sanitized (the renderer and GL too) is --sanitize.
asan="$root/build-asan-robustness"
cmake -S "$root" -B "$asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DENVSHADOW_WERROR=ON -DENVSHADOW_SANITIZE=ON \
  -DENVSHADOW_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$asan" -j"$(nproc)" --target test_robustness
cd "$asan"
env "${sanitizer_env[@]}" ctest -j"$(nproc)" --output-on-failure --no-tests=error -L unit -R '^(Robust|FuzzFindings|OneLineMessages)'
