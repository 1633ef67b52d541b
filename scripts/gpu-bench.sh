#!/usr/bin/env bash
# The GPU run, in one command: builds Release, checks that EGL reaches a hardware GPU, benches
# flyover (the paper's Table 1 scene: two figures) and default.json at 1920x1080 for N = 32, 64, 128,
# 256, each with the paper's method (cells, hard shadows) and with the commands' defaults (ratio
# shading, soft shadows), and the per-frame GPU sampler, and writes the table into
# docs/PERFORMANCE.md between the markers
#   <!-- gpu-bench:begin --> ... <!-- gpu-bench:end -->
# with the GPU's name. Takes a few minutes on a GPU machine (most of it the build).
#
#   scripts/gpu-bench.sh                      on a GPU machine: build, bench, rewrite the section
#   scripts/gpu-bench.sh --bin B [--out F]    the same with a binary built elsewhere
#   scripts/gpu-bench.sh --dry-run --bin B --out F
#                                             anywhere (llvmpipe too): tiny sizes, no build, the
#                                             section written to F (the test suite runs this)
#
# Output format (also in docs/PERFORMANCE.md): a heading naming the GPU, driver and date, the exact
# commands, then one Markdown table row per run: case, N, lights drawn, resolution, frame ms
# median / p95, FPS median, and the median GPU ms of the shadow atlas, shadowed fraction and shading
# passes.
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
  width=1920 height=1080 frames=200 warmup=20 sweep="lights=32,64,128,256" gpu_lights=128
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
common=(--width "$width" --height "$height" --frames "$frames" --warmup "$warmup" --backend egl)
# One run per case: the paper's method (cells, hard shadows) against the commands' defaults (ratio
# shading, soft shadows at half rate, MSAA 4) on flyover and default.json, and the GPU sampler.
cases=(flyover_paper flyover_defaults default_paper default_defaults flyover_fs_gpu)
declare -A cmd
cmd[flyover_paper]="bench --scene assets/scenes/flyover.json --sweep $sweep --shading cells --shadows hard"
cmd[flyover_defaults]="bench --scene assets/scenes/flyover.json --sweep $sweep"
cmd[default_paper]="bench --scene assets/scenes/default.json --sweep $sweep --shading cells --shadows hard"
cmd[default_defaults]="bench --scene assets/scenes/default.json --sweep $sweep"
cmd[flyover_fs_gpu]="bench --scene assets/scenes/flyover.json --lights $gpu_lights --method fs-gpu"
commands=()
for c in "${cases[@]}"; do
  read -r -a args <<<"${cmd[$c]}"
  "$bin" "${args[@]}" "${common[@]}" --json "$work/$c.json" >"$work/$c.txt" 2>&1 || { cat "$work/$c.txt" >&2; exit 1; }
  commands+=("$bin ${cmd[$c]} ${common[*]}")
done

python3 - "$work" "$out" "$renderer" "$dry_run" "${commands[@]}" <<'EOF'
import datetime, json, os, sys

work, out, renderer, dry_run = sys.argv[1:5]
commands = sys.argv[5:]
begin, end = "<!-- gpu-bench:begin -->", "<!-- gpu-bench:end -->"

def rows(name, label):
    d = json.load(open(os.path.join(work, name)))
    for r in d["rows"]:
        gpu = r.get("gpu_ms", {})
        med = lambda p: f"{gpu[p]['median']:.3f}" if p in gpu else "–"
        yield (f"| {label(r)} | {r['lights']} | {r['lights_drawn']} | {r['width']}×{r['height']} "
               f"| {r['frame_ms']['median']:.3f} / {r['frame_ms']['p95']:.3f} | {r['fps']['median']:.1f} "
               f"| {med('shadow atlas')} | {med('shadowed fraction')} | {med('shading')} |")

lines = [begin,
         f"### GPU: {renderer}" + (" (dry run, tiny sizes: not a measurement)" if dry_run == "1" else ""),
         "",
         f"Written by `scripts/gpu-bench.sh` on {datetime.date.today().isoformat()}; medians over the timed frames of",
         "",
         *[f"    {c}" for c in commands],
         "",
         "| case | N | drawn | resolution | frame ms med / p95 | FPS med | atlas GPU ms | fraction GPU ms | shading GPU ms |",
         "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: |"]
for scene in ("flyover", "default"):
    lines += rows(f"{scene}_paper.json", lambda r: f"{scene}, paper's method (cells, hard), {r['setting']}")
    lines += rows(f"{scene}_defaults.json", lambda r: f"{scene}, defaults (ratio, soft, half), {r['setting']}")
lines += rows("flyover_fs_gpu.json", lambda r: "flyover, fs-gpu (sampled every frame)")
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
