#!/usr/bin/env python3
"""Error per millisecond: relative RMSE against `envshadow reference` versus median frame
time, over N = 16 ... 256 lights and tile budgets of N x 128^2, 256^2 and 512^2 texels, for the two scenes a
user would pick a setting on (flyover under city, the sphere on the ground under courtyard).

The error is measured as scripts/accuracy.py measures it (its Study class: one sample per pixel centre on both
sides, at the reference's size, the sphere alone for sphere_ground); the frame time comes from `envshadow bench`
at --size (default 640x360), one bench per tile budget sweeping N, with the same settings. A point is Pareto-best
when no other point of its scene is both faster and more accurate. Writes docs/performance/error_per_ms.csv and
.png and the section between the markers in docs/PERFORMANCE.md.

    scripts/error-per-ms.py                 # everything missing from the cache, then the report
    scripts/error-per-ms.py --report-only   # the report from what the cache holds
"""
import argparse
import concurrent.futures as cf
import csv
import json
import os
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from accuracy_report import progress  # noqa: E402  (scripts/accuracy.py's package: the Study, references, plots)
from accuracy_report.cache import atomic_open, result_key  # noqa: E402
from accuracy_report.config import DEFAULTS, MAPS, ROOT, SCENES  # noqa: E402
from accuracy_report.plots import gnuplot, plot_panel, TERM  # noqa: E402
from accuracy_report.progress import log  # noqa: E402
from accuracy_report.runner import run, Study  # noqa: E402

SCENES["flyover"] = ("assets/scenes/flyover.json", 160, 90, None)
CASES = [("flyover", "city"), ("sphere_ground", "courtyard")]
NS = [16, 32, 64, 128, 256]
TILES = [128, 256, 512]
MARK_BEGIN = "<!-- error-per-ms: begin (scripts/error-per-ms.py writes this section) -->"
MARK_END = "<!-- error-per-ms: end -->"


def bench_rows(args, cache, scene, map_, tile):
    """Median frame ms per N for one tile budget, cached as the bench's own JSON."""
    w, h = args.size.split("x")
    out = f"{cache}/bench__{scene}__{map_}__{args.size}__tile{tile}__f{args.frames}.json"
    if not os.path.exists(out):
        if args.report_only:
            return {}, {}
        log(f"bench {scene} {map_} tile {tile} at {args.size} ...")
        run([args.bin, "bench", "--scene", SCENES[scene][0], "--env", MAPS[map_], "--width", w,
             "--height", h, "--frames", str(args.frames), "--warmup", "2", "--tile", str(tile), "--msaa", "1",
             "--sweep", "lights=" + ",".join(map(str, NS)), "--json", out + ".tmp.json"])
        with open(out + ".tmp.json") as f:
            data = json.load(f)
        data["load_average"] = os.getloadavg()[0]  # after the run: what the machine was doing meanwhile
        with atomic_open(out) as f:
            json.dump(data, f)
        os.remove(out + ".tmp.json")
    with open(out) as f:
        data = json.load(f)
    return {row["lights"]: row for row in data["rows"]}, data


def pareto(points):
    """The points no other point beats on both frame time and error (ties keep both)."""
    return {i for i, (t, e) in enumerate(points)
            if not any((t2 <= t and e2 <= e) and (t2 < t or e2 < e) for t2, e2 in points)}


def collect(args, study):
    rows, machine, loads = [], None, []
    for scene, map_ in CASES:
        for tile in TILES:
            frames, data = bench_rows(args, study.cache, scene, map_, tile)
            machine = machine or data.get("renderer")
            loads.append(data.get("load_average", float("nan")))
            for n in NS:
                key = result_key(scene, map_, "lloyd", n, dict(DEFAULTS, tile=tile), args.error)
                r = study.results.get(key)
                if not r or n not in frames:
                    continue
                rows.append({"scene": scene, "map": map_, "lights": n, "tile": tile,
                             "drawn": frames[n].get("lights_drawn", n),
                             "frame_ms": frames[n]["frame_ms"]["median"],
                             "atlas_ms": frames[n]["gpu_ms"].get("shadow atlas", {}).get("median", 0.0),
                             "rel_rmse": r["rel_rmse"]})
    for scene, map_ in CASES:
        mine = [r for r in rows if r["scene"] == scene]
        best = pareto([(r["frame_ms"], r["rel_rmse"]) for r in mine])
        for i, r in enumerate(mine):
            r["pareto"] = i in best
    return rows, machine, loads


def write_plot(rows, path):
    s = TERM.format(w=900, h=340) + f"set output '{path}'\nset multiplot layout 1,{len(CASES)}\n"
    s += f"set logscale xy\nset xlabel 'median frame time (ms, {ARGS.size}, llvmpipe)'\n"
    s += "set ylabel 'relative RMSE (%)'\nset grid\nset key top right\n"
    for scene, map_ in CASES:
        series = []
        for tile in TILES:
            pts = [f"{r['frame_ms']:.2f} {100 * r['rel_rmse']:.4f}" for r in rows
                   if r["scene"] == scene and r["tile"] == tile]
            series.append((f"budget N x {tile}^2", pts))
        s += plot_panel(f"{scene} / {map_}: N = 16 ... 256 along each line", series)
    s += "unset multiplot\n"
    gnuplot(s)


def section(rows, machine, load):
    out = [MARK_BEGIN, "", "## Error per millisecond", ""]
    out.append(f"`scripts/error-per-ms.py` on {machine} through EGL (load average {load} on the 2 cores when the "
               f"benches ran). Error: relative RMSE against `envshadow reference` (0.5% standard error per pixel) "
               f"as docs/ACCURACY.md measures it, at the reference's size (flyover 160×90 at time 0, every object "
               f"pixel; sphere_ground 160×120, the sphere only), lloyd, `--tile-sizes share`, hard shadows, cells "
               f"shading, one sample per pixel. Frame time: `envshadow bench` at {ARGS.size}, `--msaa 1`, median "
               f"of {ARGS.frames} frames after 2 warm-up, the same settings. **bold**: Pareto-best (no other "
               f"point of the scene is both faster and more accurate). Figures: docs/performance/error_per_ms.csv "
               f"and the plot below.")
    out.append("")
    out.append("![error against frame time](performance/error_per_ms.png)")
    for scene, map_ in CASES:
        out += ["", f"**{scene} / {map_}**", "",
                "| N | tile budget | frame ms | shadow atlas ms | relative RMSE |", "| ---: | ---: | ---: | ---: | ---: |"]
        for r in sorted((r for r in rows if r["scene"] == scene), key=lambda r: (r["tile"], r["lights"])):
            b = "**" if r["pareto"] else ""
            out.append(f"| {b}{r['lights']}{b} | N × {r['tile']}² | {b}{r['frame_ms']:.0f}{b} | {r['atlas_ms']:.0f} | "
                       f"{b}{100 * r['rel_rmse']:.2f}%{b} |")
    out += ["", pick_text(rows), "", MARK_END]
    return "\n".join(out) + "\n"


KNEE = 1.15  # the knee: the fastest point within this factor of the scene's lowest error


def knee(rows, scene):
    mine = [r for r in rows if r["scene"] == scene]
    best = min(r["rel_rmse"] for r in mine)
    return min((r for r in mine if r["rel_rmse"] <= KNEE * best), key=lambda r: r["frame_ms"])


def pick_text(rows):
    out = [f"**Which point to pick.** Past a point, more lights or texels buy little: the knee of each curve, the "
           f"fastest point within {KNEE:.2f}× of its scene's lowest error, is"]
    knees = {scene: knee(rows, scene) for scene, _ in CASES}
    out.append(", ".join(f"{scene} N = {k['lights']} at N × {k['tile']}² ({100 * k['rel_rmse']:.2f}% in "
                         f"{k['frame_ms']:.0f} ms)" for scene, k in knees.items()) + ".")
    default = next((r for r in rows if r["scene"] == CASES[0][0] and r["lights"] == 128 and r["tile"] == 256), None)
    if default:
        k = knees[CASES[0][0]]
        same = (k["lights"], k["tile"]) == (128, 256)
        out.append(f"The defaults (N = 128, a budget of N × 256²) are {'the flyover knee' if same else 'not the flyover knee'}: "
                   f"{100 * default['rel_rmse']:.2f}% in {default['frame_ms']:.0f} ms on flyover.")
        if knees[CASES[1][0]]["lights"] < k["lights"]:
            out.append("The lone sphere needs fewer lights: the figure's shadow on the other figure is what needs "
                       "more.")
    return " ".join(out)


def replace_section(path, text):
    with open(path) as f:
        doc = f.read()
    if MARK_BEGIN in doc:
        head, rest = doc.split(MARK_BEGIN, 1)
        tail = rest.split(MARK_END, 1)[1]
        doc = head + text.rstrip("\n") + tail
    else:
        doc = doc.rstrip("\n") + "\n\n" + text
    with atomic_open(path) as f:
        f.write(doc)


def self_test():
    """pareto(), knee() and the section on made-up points (no build needed); 0 when all hold."""
    global ARGS
    ARGS = argparse.Namespace(size="640x360", frames=5)
    faults = []
    # (time, error): (3, 3) is beaten by (2, 2); the tie (1, 5)/(1, 5) keeps both; (4, 1) is best in error.
    got = pareto([(1, 5), (2, 2), (3, 3), (4, 1), (1, 5)])
    if got != {0, 1, 3, 4}:
        faults.append(f"pareto: {sorted(got)}")
    rows = []
    for scene, _ in CASES:
        for n, t, ms, e in [(16, 128, 100, 0.030), (128, 256, 900, 0.0160), (256, 256, 2000, 0.0150),
                            (64, 256, 400, 0.0200), (128, 512, 1200, 0.0159)]:
            rows.append({"scene": scene, "map": "m", "lights": n if scene == "flyover" else n // 2, "tile": t,
                         "drawn": n, "frame_ms": ms, "atlas_ms": ms / 2, "rel_rmse": e, "pareto": False})
    k = knee(rows, "flyover")  # within 1.15 x 1.5% = 1.725%: 900, 1200 and 2000 ms; the fastest is 900
    if (k["lights"], k["tile"]) != (128, 256):
        faults.append(f"knee: {k}")
    text = pick_text(rows)
    if "are the flyover knee" not in text or "needs fewer lights" not in text:
        faults.append(f"pick text: {text}")
    for r in rows:
        r["pareto"] = True
    if sum(line.startswith("| **") for line in section(rows, "a GPU", "1.0").splitlines()) != len(rows):
        faults.append("section: not every Pareto row is bold")
    for f in faults:
        print("error-per-ms self-test:", f)
    return 1 if faults else 0


def main():
    if "--self-test" in sys.argv[1:]:
        sys.exit(self_test())
    global ARGS
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--bin", default="build/app/envshadow")
    p.add_argument("--cache", default="build/error-per-ms")
    p.add_argument("--error", type=float, default=0.005, help="reference relative standard error per pixel")
    p.add_argument("--size", default="640x360", help="resolution of the frame-time benches")
    p.add_argument("--frames", type=int, default=5)
    p.add_argument("--jobs", type=int, default=2, help="renders in parallel (references: one at a time)")
    p.add_argument("--report-only", action="store_true", help="write the report from the cache, measure nothing")
    p.add_argument("--fresh", action="store_true", help="forget cached render/compare results")
    args = ARGS = p.parse_args()
    os.chdir(ROOT)
    study = Study(args)
    if not args.report_only:
        refs = cf.ThreadPoolExecutor(max_workers=1)
        refs.submit(study.make_references, CASES)
        jobs = [(s, m, n, t) for s, m in CASES for t in TILES for n in NS]
        progress.start(len(jobs))
        with cf.ThreadPoolExecutor(max_workers=args.jobs) as ex:
            for f in [ex.submit(study.measure, s, m, "lloyd", n, tile=t) for s, m, n, t in jobs]:
                f.result()
        refs.shutdown()
        progress.finish()
    else:
        for case in CASES:
            study.ref_ready.setdefault(case, threading.Event()).set()
    rows, machine, loads = collect(args, study)
    load = f"{min(loads):.1f}–{max(loads):.1f}" if loads else "?"
    if not rows:
        sys.exit("error-per-ms: nothing measured yet (run without --report-only)")
    os.makedirs(os.path.join(ROOT, "docs/performance"), exist_ok=True)
    with atomic_open(os.path.join(ROOT, "docs/performance/error_per_ms.csv")) as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    write_plot(rows, os.path.join(ROOT, "docs/performance/error_per_ms.png"))
    replace_section(os.path.join(ROOT, "docs/PERFORMANCE.md"), section(rows, machine, load))
    log(f"wrote docs/PERFORMANCE.md's error-per-ms section, docs/performance/error_per_ms.{{csv,png}} "
        f"({len(rows)} points, {time.strftime('%H:%M')})")


if __name__ == "__main__":
    main()
