#!/bin/bash
# scripts/decompose-timing.sh [full|upper] [RUNS]: per blender map, alternated runs of
# `envshadow decompose` (the seconds it prints) and `bench_decompose --cold` (the same interval),
# medians and their ratio, and the load average (docs/PERFORMANCE.md, "Decomposition"). Needs build/.
set -eu
H=${1:-full}; R=${2:-5}; W=/usr/share/blender/datafiles/studiolights/world
cd "$(dirname "$0")/.."
for m in city courtyard forest interior night studio sunrise sunset; do
  cli=(); bc=()
  for r in $(seq $R); do
    cli+=($(build/app/envshadow decompose --env $W/$m.exr --hemisphere $H 2>/dev/null | head -1 | sed -E 's/.* ([0-9.]+) s.*/\1/'))
    bc+=($(build/tests/bench/bench_decompose --cold $m $H))
  done
  python3 -c "
import statistics as s,sys
a=[float(x)*1e3 for x in '${cli[*]}'.split()]; b=[float(x)*1e3 for x in '${bc[*]}'.split()]
print('%-10s printed %6.1f  bench-cold %6.1f  ratio %.2f   printed %s' % ('$m', s.median(a), s.median(b), s.median(a)/s.median(b), ' '.join('%.0f'%x for x in sorted(a))))"
done
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
