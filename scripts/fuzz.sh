#!/usr/bin/env bash
# Builds the libFuzzer targets (clang-14, ASan + UBSan, in build-fuzz/) and runs each for a bounded
# time, one after the other (docs/ROBUSTNESS.md).
#   scripts/fuzz.sh                     every target, 60 s each
#   scripts/fuzz.sh --seconds 600 gltf  one target for 10 minutes
#   scripts/fuzz.sh --run-only ...      do not configure or build (ctest -L fuzz uses this)
# Corpora grow in build-fuzz/fuzz/corpus/TARGET, seeded from the generated seed files, the earlier
# findings in tests/data/fuzz/TARGET and tests/fuzz/TARGET.dict. A finding is written to
# build-fuzz/fuzz/findings/TARGET/ and makes the script fail; copy it to tests/data/fuzz/TARGET/
# once fixed (the robustness tests replay that folder in the default suite).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ENVSHADOW_BUILD_DIR:-$root/build-fuzz}"
all_targets=(gltf scene exr hdr)

seconds=60
run_only=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --run-only) run_only=1; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")
case "$seconds" in ''|*[!0-9]*) echo "fuzz.sh: --seconds needs a whole number" >&2; exit 2 ;; esac

if [ $run_only -eq 0 ]; then
  "$root/scripts/install-deps.sh"
  CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DENVSHADOW_FUZZ=ON -DENVSHADOW_SANITIZE=ON -DENVSHADOW_BUILD_BENCHMARKS=OFF >/dev/null
  build_targets=()
  for t in "${targets[@]}"; do build_targets+=("fuzz_$t"); done
  cmake --build "$build" -j"$(nproc)" --target "${build_targets[@]}"
fi

fuzz_dir="$build/fuzz"
seeds="$build/tests/fuzz/seeds"
mkdir -p "$fuzz_dir"
failed=0
printf '%-6s %8s %12s %9s %s\n' target seconds executions findings log
for t in "${targets[@]}"; do
  exe="$build/tests/fuzz/fuzz_$t"
  if [ ! -x "$exe" ]; then echo "fuzz.sh: $exe is not built" >&2; exit 2; fi
  corpus="$fuzz_dir/corpus/$t" findings="$fuzz_dir/findings/$t" log="$fuzz_dir/$t.log"
  mkdir -p "$corpus" "$findings"
  inputs=("$corpus" "$seeds/$t")
  [ -d "$root/tests/data/fuzz/$t" ] && inputs+=("$root/tests/data/fuzz/$t")
  options=(-max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 -print_final_stats=1
           -artifact_prefix="$findings/")
  [ -f "$root/tests/fuzz/$t.dict" ] && options+=(-dict="$root/tests/fuzz/$t.dict")
  before=$(find "$findings" -type f | wc -l)
  # Leaks are findings too, but the process keeps running after one only with -detect_leaks=1 (default).
  rc=0
  ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    "$exe" "${options[@]}" "${inputs[@]}" >"$log" 2>&1 || rc=$?
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  after=$(find "$findings" -type f | wc -l)
  printf '%-6s %8s %12s %9s %s\n' "$t" "$seconds" "${executions:-?}" "$((after - before))" "$log"
  if [ $rc -ne 0 ] || [ "$after" -gt "$before" ]; then
    failed=1
    echo "fuzz.sh: $t: finding (exit $rc); see $log and $findings/" >&2
    grep -m3 -E 'ERROR: |runtime error|contract violated|SUMMARY' "$log" >&2 || true
  fi
done
exit $failed
