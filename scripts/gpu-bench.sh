#!/usr/bin/env bash
# The GPU run, in one command: builds Release, checks that EGL reaches a hardware GPU,
# benches flyover (the paper's Table 1 scene: two figures) at 1920x1080 for N = 64, 128, 256 in both
# shading modes (the paper's cells, the ratio estimator) and the per-frame GPU sampler, and writes the table into docs/PERFORMANCE.md between the markers
#   <!-- gpu-bench:begin --> ... <!-- gpu-bench:end -->
# with the GPU's name. Takes a few minutes on a GPU machine (most of it the build).
#
#   scripts/gpu-bench.sh                      on a GPU machine: build, bench, rewrite the section
#   scripts/gpu-bench.sh --dry-run --bin B --out F
#                                             anywhere (llvmpipe too): tiny sizes, no build, the
#                                             section written to F (the test suite runs this)
#
# Output format (also in docs/PERFORMANCE.md): a heading naming the GPU, driver and date, the exact
# commands, then one Markdown table row per run: case, N, lights drawn, resolution, frame ms
# median / p95, FPS median, and the median GPU ms of the shadow atlas and shading passes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

dry_run=0
bin=""
out="docs/PERFORMANCE.md"
while [ $# -gt 0 ]; do
  case "$1" in
    --dry-run) dry_run=1 ;;
    --bin) bin="$2"; shift ;;
    --out) out="$2"; shift ;;
    *) echo "gpu-bench.sh: unknown argument $1 (see the comment at the top of the script)" >&2; exit 2 ;;
  esac
  shift
done

if [ -z "$bin" ]; then
  scripts/install-deps.sh
  cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release -DENVSHADOW_BUILD_TESTS=OFF \
    -DENVSHADOW_BUILD_BENCHMARKS=OFF >/dev/null
  cmake --build build-release --target envshadow -j"$(nproc)" >/dev/null
  bin="build-release/app/envshadow"
fi
[ -x "$bin" ] || { echo "gpu-bench.sh: $bin is not an executable" >&2; exit 2; }

# The EGL line of --version: "  egl     yes: <renderer>, <GL version> (<EGL platform>)".
egl_line="$("$bin" --version | grep -E '^ +egl +yes: ' || true)"
[ -n "$egl_line" ] || { echo "gpu-bench.sh: EGL gives no OpenGL 4.5 context ($("$bin" --version | grep egl))" >&2; exit 1; }
renderer="${egl_line#*yes: }"
if [ "$dry_run" = 0 ] && { [[ "$renderer" != *"EGL device"* ]] || [[ "$renderer" == *llvmpipe* ]]; }; then
  echo "gpu-bench.sh: EGL does not reach a hardware GPU through its device platform: $renderer" >&2
  exit 1
fi

if [ "$dry_run" = 1 ]; then
  width=96 height=54 frames=3 warmup=1 sweep="lights=8,16" gpu_lights=16
else
  width=1920 height=1080 frames=200 warmup=20 sweep="lights=64,128,256" gpu_lights=128
fi
scene="assets/scenes/flyover.json"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
common=(--scene "$scene" --width "$width" --height "$height" --frames "$frames" --warmup "$warmup" --backend egl)
cmd_cells=("$bin" bench "${common[@]}" --sweep "$sweep" --shading cells)
cmd_ratio=("$bin" bench "${common[@]}" --sweep "$sweep" --shading ratio)
cmd_fs_gpu=("$bin" bench "${common[@]}" --lights "$gpu_lights" --method fs-gpu)
"${cmd_cells[@]}" --json "$work/cells.json" >"$work/cells.txt" 2>&1 || { cat "$work/cells.txt" >&2; exit 1; }
"${cmd_ratio[@]}" --json "$work/ratio.json" >"$work/ratio.txt" 2>&1 || { cat "$work/ratio.txt" >&2; exit 1; }
"${cmd_fs_gpu[@]}" --json "$work/fs_gpu.json" >"$work/fs_gpu.txt" 2>&1 || { cat "$work/fs_gpu.txt" >&2; exit 1; }

python3 - "$work" "$out" "$renderer" "$dry_run" "${cmd_cells[*]}" "${cmd_ratio[*]}" "${cmd_fs_gpu[*]}" <<'EOF'
import datetime, json, os, sys

work, out, renderer, dry_run, cmd_cells, cmd_ratio, cmd_fs_gpu = sys.argv[1:]
begin, end = "<!-- gpu-bench:begin -->", "<!-- gpu-bench:end -->"

def rows(name, label):
    d = json.load(open(os.path.join(work, name)))
    for r in d["rows"]:
        gpu = r.get("gpu_ms", {})
        med = lambda p: f"{gpu[p]['median']:.3f}" if p in gpu else "–"
        yield (f"| {label(r)} | {r['lights']} | {r['lights_drawn']} | {r['width']}×{r['height']} "
               f"| {r['frame_ms']['median']:.3f} / {r['frame_ms']['p95']:.3f} | {r['fps']['median']:.1f} "
               f"| {med('shadow atlas')} | {med('shading')} |")

lines = [begin,
         f"### GPU: {renderer}" + (" (dry run, tiny sizes: not a measurement)" if dry_run == "1" else ""),
         "",
         f"Written by `scripts/gpu-bench.sh` on {datetime.date.today().isoformat()}; medians over the timed frames of",
         "",
         f"    {cmd_cells}",
         f"    {cmd_ratio}",
         f"    {cmd_fs_gpu}",
         "",
         "| case | N | drawn | resolution | frame ms med / p95 | FPS med | atlas GPU ms | shading GPU ms |",
         "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: |"]
lines += rows("cells.json", lambda r: f"flyover, lloyd, cells shading, {r['setting']}")
lines += rows("ratio.json", lambda r: f"flyover, lloyd, ratio shading, {r['setting']}")
lines += rows("fs_gpu.json", lambda r: "flyover, fs-gpu (sampled every frame)")
lines.append(end)
section = "\n".join(lines) + "\n"

text = open(out).read() if os.path.exists(out) else ""
if begin in text and end in text:
    head, rest = text.split(begin, 1)
    text = head + section + rest.split(end, 1)[1].lstrip("\n")
else:
    text = text + ("\n" if text and not text.endswith("\n") else "") + section
tmp = out + ".tmp"
with open(tmp, "w") as f:
    f.write(text)
os.replace(tmp, out)  # nothing half-written
print(f"gpu-bench.sh: wrote the GPU table to {out}")
EOF
