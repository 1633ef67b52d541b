"""Accuracy report: writes docs/ACCURACY.md, docs/PAPER.md and the plots in docs/accuracy/.

    scripts/accuracy.py            # the committed report (a subset of scenes x maps, see COVERAGE)
    scripts/accuracy.py --full     # every scene x map, every method x N (hours on a loaded 2-core VM)
    scripts/accuracy.py --self-test  # the cache keys and the targets over seeds on made-up results
    scripts/accuracy.py --from-csv --forget engine   # a fresh clone: the committed results, engine's redone

Needs a build (build/app/envshadow, build/tests/brdf/brdf_figures) and gnuplot. Reference images
(`envshadow reference`, CPU Monte Carlo) are cached in build/accuracy/ref/ by scene, map, size and error
target, and every render+compare result in build/accuracy/results.json, so a rerun only computes what is
missing; --fresh forgets the results (not the references). --from-csv starts an empty cache from the
committed docs/accuracy/results.csv, and --forget SCENE,... drops a scene's results and references (after
a change that moves its images); references are made only for results that are missing. Nothing here is
a test threshold: the targets are reported against, not asserted.
"""
import argparse
import concurrent.futures as cf
import os
import sys
import threading
import time

from .config import (DEFAULTS, DIFFUSE_PAIRS, GRID_PAIRS, HEMISPHERE_PAIRS, HEMISPHERE_SEEDS, HEMISPHERES, MAPS,
    METHODS, NS, ROOT, SCENE_DIR, SCENES, SEED_PAIRS, SEEDS, SHADING_NS, SHADING_PAIRS, SPECULAR_PAIRS, TABLE_PAIRS,
    TILE_PAIRS, TILES)
from .progress import finish, log, start
from .cache import atomic_open, key_fields, result_key
from .runner import bench, decomposition_stats, run, Study
from .plots import fig7_three_ways, paper_figures, plot_error_vs_n, plot_error_vs_time
from .report import write_accuracy, write_paper
from .selftest import self_test


def main():
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--full", action="store_true", help="every scene x map in every study")
    p.add_argument("--jobs", type=int, default=2, help="renders in parallel (references: always one at a time)")
    p.add_argument("--error", type=float, default=0.005, help="reference relative standard error per pixel")
    p.add_argument("--bin", default="build/app/envshadow")
    p.add_argument("--figures", default="build/tests/brdf/brdf_figures")
    p.add_argument("--cache", default="build/accuracy")
    p.add_argument("--fresh", action="store_true", help="forget cached render/compare results")
    p.add_argument("--bench-size", default="320x180", help="resolution of the frame-time benches")
    p.add_argument("--bench-frames", type=int, default=3)
    p.add_argument("--report-only", action="store_true",
                   help="write the documents from cached results only (nothing rendered; for editing the report)")
    p.add_argument("--no-grid-methods", default="", help="comma list of methods to leave out of the N grid")
    p.add_argument("--from-csv", action="store_true",
                   help="start the result cache from docs/accuracy/results.csv (a fresh clone: only missing results "
                        "are rendered, and only their references made)")
    p.add_argument("--forget", default="", help="comma list of scenes whose cached results and references to drop")
    args = p.parse_args()
    t0 = time.time()
    os.chdir(ROOT)
    for exe in (args.bin, args.figures):
        if not os.path.exists(exe):
            sys.exit(f"accuracy.py: {exe} not found (build first: cmake --build build --target envshadow brdf_figures)")
    study = Study(args)
    if args.from_csv and os.path.exists("docs/accuracy/results.csv"):
        study.import_csv("docs/accuracy/results.csv")
    forget = [sc for sc in args.forget.split(",") if sc]
    unknown = [sc for sc in forget if sc not in SCENES]
    if unknown:
        sys.exit(f"accuracy.py: --forget: no scene {', '.join(unknown)} (scenes: {', '.join(SCENES)})")
    study.forget(forget)
    outdir = "docs/accuracy"
    os.makedirs(outdir, exist_ok=True)

    all_pairs = [(s, m) for s in SCENES for m in MAPS]
    grid_pairs = all_pairs if args.full else GRID_PAIRS
    table_pairs = all_pairs if args.full else TABLE_PAIRS
    spec_pairs = [p_ for p_ in all_pairs if p_[0] in ("sphere_n10", "sphere_n100")] if args.full else SPECULAR_PAIRS
    diff_pairs = [p_ for p_ in all_pairs if not p_[0].startswith("sphere")] if args.full else DIFFUSE_PAIRS
    tile_pairs = [p_ for p_ in all_pairs if not p_[0].startswith("sphere")] if args.full else TILE_PAIRS
    shading_pairs = all_pairs if args.full else SHADING_PAIRS

    def results_for(scene, map_, m, n, **o):
        return study.results.get(result_key(scene, map_, m, n, dict(DEFAULTS, **o), args.error))
    study.results_for = results_for

    # References first (one at a time), in the order the studies need them.
    needed = []
    seed_pairs_all = [p_ for p_ in all_pairs if p_ in set(table_pairs)] if args.full else SEED_PAIRS
    hemisphere_pairs = all_pairs if args.full else HEMISPHERE_PAIRS
    for pr in (grid_pairs + table_pairs + spec_pairs + diff_pairs + tile_pairs + seed_pairs_all + hemisphere_pairs
               + shading_pairs):
        if pr not in needed:
            needed.append(pr)
    report_refs = list(needed)

    # Every render job (deduplicated by the result cache key inside measure()).
    skip = set(filter(None, args.no_grid_methods.split(",")))
    jobs = []
    def covered(scene, map_, m, n, in_grid):
        return not (m in skip and in_grid)

    for scene, map_ in table_pairs:
        for m in METHODS:
            if covered(scene, map_, m, 128, False):
                jobs.append((scene, map_, m, 128, {}))
    for scene, map_ in grid_pairs:
        for m in METHODS:
            for n in NS:
                if covered(scene, map_, m, n, True):
                    jobs.append((scene, map_, m, n, {}))
    for scene, map_ in spec_pairs:
        for spec in ("blended", "single"):
            for cap in ("solid-angle", "weighted"):
                jobs.append((scene, map_, "lloyd", 128, {"specular": spec, "cap": cap}))
    for scene, map_ in diff_pairs:
        for d in ("center", "cap"):
            jobs.append((scene, map_, "lloyd", 128, {"diffuse": d}))
    for scene, map_ in shading_pairs:
        for n in SHADING_NS:
            for shading in ("cells", "ratio"):
                jobs.append((scene, map_, "lloyd", n, {"shading": shading}))
    for scene, map_ in tile_pairs:
        for t in TILES:
            for sizes in ("uniform", "share"):
                jobs.append((scene, map_, "lloyd", 128, {"tile": t, "tile_sizes": sizes}))
    seed_pairs = [p_ for p_ in all_pairs if p_ in set(table_pairs)] if args.full else SEED_PAIRS
    for scene, map_ in seed_pairs:
        for m in ("lloyd", "random"):
            for seed in SEEDS:
                jobs.append((scene, map_, m, 128, {"seed": seed}))
    for scene, map_ in hemisphere_pairs:
        for hemisphere in HEMISPHERES:
            for seed in HEMISPHERE_SEEDS:
                jobs.append((scene, map_, "lloyd", 128, {"seed": seed, "hemisphere": hemisphere}))
    # Studies share cases (lloyd at N = 128 with the defaults is in most): run each once, or two renders
    # of the same case would write, compare and remove the same image at once.
    unique = {}
    for j in jobs:
        unique.setdefault(result_key(j[0], j[1], j[2], j[3], dict(DEFAULTS, **j[4]), args.error), j)
    jobs = [] if args.report_only else list(unique.values())
    report_keys = set(unique)  # what this report is made of (the cache may hold more)
    order = {pr: i for i, pr in enumerate(needed)}
    jobs.sort(key=lambda j: order[(j[0], j[1])])  # stable: renders follow the references as they arrive
    # References only where a result is missing (cached results need none), one at a time in their own thread.
    missing = {(j[0], j[1]) for j in jobs
               if result_key(j[0], j[1], j[2], j[3], dict(DEFAULTS, **j[4]), args.error) not in study.results}
    ref_thread = threading.Thread(target=study.make_references, args=([pr for pr in needed if pr in missing],),
                                  daemon=True)
    ref_thread.start()
    failed = []
    start(sum(1 for j in jobs if result_key(j[0], j[1], j[2], j[3], dict(DEFAULTS, **j[4]), args.error)
              not in study.results))
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futs = [ex.submit(study.measure, s, m, meth, n, **o) for s, m, meth, n, o in jobs]
        for j, f in zip(jobs, futs):
            try:
                f.result()
            except RuntimeError as e:
                failed.append(f"{j}: {str(e).splitlines()[0]}")
    ref_thread.join()
    finish()
    for msg in failed:
        log(f"FAILED {msg}")

    # Frame times: one sweep over N per grid scene, and the paper's Table 1 scenes.
    bw, bh = map(int, args.bench_size.split("x"))
    sweep = "lights=" + ",".join(map(str, NS))
    frame_ms, bench_rows = {}, {}
    for scene in sorted({s for s, _ in grid_pairs}):
        if args.report_only and not os.path.exists(f"{study.cache}/bench_{scene}_{bw}x{bh}_f{args.bench_frames}.json"):
            continue
        b = bench(args, study.cache, SCENES[scene][0], sweep, bw, bh, args.bench_frames, scene)
        frame_ms[scene] = {row["lights"]: row["frame_ms"]["median"] for row in b["rows"]}
        bench_rows[scene] = b
    table1 = {}
    for name in ("flyover_single", "flyover"):
        if args.report_only and not os.path.exists(f"{study.cache}/bench_{name}_{bw}x{bh}_f{args.bench_frames}.json"):
            continue
        table1[name] = bench(args, study.cache, f"assets/scenes/{name}.json", "lights=64,128", bw, bh,
                             args.bench_frames, name)

    dstats = decomposition_stats(args, study.cache)

    # Plots
    plot_error_vs_n(study, grid_pairs, f"{outdir}/error_vs_n.png")
    plot_error_vs_time(study, grid_pairs, frame_ms, f"{outdir}/error_vs_frame_time.png")
    checks, fig6_summary, fig5_cross = paper_figures(args, outdir)

    # Images for the paper's Figs. 7 and 8
    for spec in ("single", "blended"):
        out = f"{outdir}/fig7_{spec}.png"
        if args.report_only and os.path.exists(out):
            continue
        run([args.bin, "render", "--scene", f"{SCENE_DIR}/fig7.json", "--lights", "128", "--width", "480",
             "--height", "200", "--specular", spec, "--shading", "cells", "--shadows", "hard", "--out", out])
    for t in (0.0, 1.5):
        if args.report_only and os.path.exists(f"{outdir}/fig8_t{t:g}.png"):
            continue
        run([args.bin, "render", "--scene", "assets/scenes/flyover.json", "--lights", "128", "--width", "400",
             "--height", "225", "--time", str(t), "--shading", "cells", "--shadows", "hard",
             "--out", f"{outdir}/fig8_t{t:g}.png"])

    fig7_three = fig7_three_ways(args, study, outdir)

    # CSV of every result
    with atomic_open(f"{outdir}/results.csv") as f:
        f.write("scene,map,method,N,tile,specular,cap,diffuse,size,ref_error,seed,hemisphere,tile_sizes,shading,hemisphere_used,lights_drawn,"
                "rel_rmse,psnr,pixels,render_s\n")
        for k in sorted(study.results):
            if report_keys and k not in report_keys:
                continue
            r = study.results[k]
            f.write(",".join(key_fields(k)) + f",{r.get('hemisphere_used', '')},{r.get('lights_drawn', '')}"
                    f",{r['rel_rmse']:.6f},{r['psnr']:.3f},{r['pixels']},{r['render_s']:.2f}\n")

    ctx = dict(args=args, study=study, grid_pairs=grid_pairs, table_pairs=table_pairs, spec_pairs=spec_pairs,
               shading_pairs=shading_pairs,
               diff_pairs=diff_pairs, tile_pairs=tile_pairs, seed_pairs=seed_pairs_all, hemisphere_pairs=hemisphere_pairs,
               report_refs=report_refs, report_keys=report_keys, frame_ms=frame_ms, bench_rows=bench_rows,
               table1=table1, checks=checks, fig7_three=fig7_three, fig6_summary=fig6_summary, fig5_cross=fig5_cross,
               seconds=time.time() - t0, bench_size=(bw, bh), dstats=dstats)
    write_accuracy(ctx, "docs/ACCURACY.md")
    write_paper(ctx, "docs/PAPER.md")
    log(f"done in {time.time() - t0:.0f} s: docs/ACCURACY.md, docs/PAPER.md, {outdir}/")
