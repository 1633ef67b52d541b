#!/usr/bin/env bash
# scripts/gpu-bench.sh --dry-run on whatever GL this machine has: it must write one GPU section
# between its markers, keep the rest of the file, replace (not append) on a second run, and refuse
# a missing binary. Usage: gpu_bench_dry_run.sh SOURCE_DIR ENVSHADOW_EXE SCRATCH_DIR
set -euo pipefail
src="$1" exe="$2" scratch="$3"
rm -rf "$scratch" && mkdir -p "$scratch"
doc="$scratch/PERFORMANCE.md"
printf '# Performance\n\nbefore\n\n<!-- gpu-bench:begin -->\nstale\n<!-- gpu-bench:end -->\n\nafter\n' >"$doc"
fail() { echo "FAIL: $*" >&2; cat "$doc" >&2; exit 1; }

for run in 1 2; do
  "$src/scripts/gpu-bench.sh" --dry-run --bin "$exe" --out "$doc" >/dev/null
  [ "$(grep -c '<!-- gpu-bench:begin -->' "$doc")" = 1 ] || fail "run $run: not exactly one begin marker"
  [ "$(grep -c '<!-- gpu-bench:end -->' "$doc")" = 1 ] || fail "run $run: not exactly one end marker"
  grep -q '^before$' "$doc" && grep -q '^after$' "$doc" || fail "run $run: text around the section lost"
  grep -q stale "$doc" && fail "run $run: the old section was kept"
  grep -q '^### GPU: .*(dry run' "$doc" || fail "run $run: no heading naming the renderer"
  # Rows: N = 8 and 16 (the sweep) for both scenes with the paper's method and the defaults, and the
  # GPU sampler at 16, each once with a positive frame time.
  for case in "flyover, paper's method (cells, hard), lights=8 | 8" "flyover, paper's method (cells, hard), lights=16 | 16" \
              "flyover, defaults (ratio, soft, half), lights=8 | 8" "flyover, defaults (ratio, soft, half), lights=16 | 16" \
              "default, paper's method (cells, hard), lights=8 | 8" "default, defaults (ratio, soft, half), lights=16 | 16" \
              "flyover, fs-gpu (sampled every frame) | 16"; do
    rows="$(grep -F "| $case | " "$doc" | grep -E '\| 96×54 \| [0-9.]+ / [0-9.]+ \| [0-9.]+ \|' || true)"
    [ "$(printf '%s' "$rows" | grep -c .)" = 1 ] || fail "run $run: not one row for \"$case\""
    ms="$(echo "$rows" | awk -F'|' '{split($6, a, "/"); print a[1] + 0}')"
    awk -v ms="$ms" 'BEGIN { exit !(ms > 0) }' || fail "run $run: \"$case\" frame time $ms"
  done
done

if "$src/scripts/gpu-bench.sh" --dry-run --bin "$scratch/no-such-envshadow" --out "$doc" 2>/dev/null; then
  fail "a missing binary was accepted"
fi
echo "gpu-bench dry run: ok"
