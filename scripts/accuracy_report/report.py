"""docs/ACCURACY.md and docs/PAPER.md."""
import json
import os
import platform

from .config import DEFAULTS, HEMISPHERE_SEEDS, METHODS, NS, ROOT, SCENES, SEEDS, SHADING_NS, TILES
from .cache import atomic_open, key_fields
from .values import cell, drawn_range, pct, rr, seed_values, spread
from .plots import FIG7_ERROR, FIG7_N, FIG7_SCENE, FIG7_SIZE
from .targets import target_rows


# ---- Markdown ----------------------------------------------------------------------------------

def machine_line(ctx):
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    renderer = next(iter(ctx["bench_rows"].values()))["renderer"] if ctx["bench_rows"] else "?"
    load = os.getloadavg()[0]
    return (f"{platform.machine()} VM, {os.cpu_count()} cores ({cpu}), GL renderer `{renderer}`, "
            f"load average {load:.1f} when the report was written (the machine is shared)")


def paired_table(w, pairs, values, headings, results):
    """A table with two columns (headings(v), results(scene, map, v)) for each of `values`, a row per pair."""
    w("| scene / map | " + " | ".join(" | ".join(headings(v)) for v in values) + " |")
    w("| --- |" + " ---: |" * (2 * len(values)))
    for s, m in pairs:
        w(f"| {s} / {m} | " + " | ".join(" | ".join(cell(x) for x in results(s, m, v)) for v in values) + " |")


def scene_has_ground(scene):
    with open(os.path.join(ROOT, SCENES[scene][0])) as f:
        return any(o.get("ground") for o in json.load(f).get("objects", []))


def hemisphere_said(ctx):
    """What the renders with --hemisphere auto reported decomposing, so the defaults line stays true."""
    st = ctx["study"]
    grounds = [s for s in SCENES if scene_has_ground(s)]
    said = [st.results[k].get("hemisphere_used") for k in ctx["report_keys"]
            if k in st.results and key_fields(k)[11] == "auto"]
    said = [x for x in said if x]
    text = (": every scene here has a ground" if len(grounds) == len(SCENES)
            else f": {', '.join(grounds) or 'no scene'} of the scenes here have one")
    if said:
        upper = sum(1 for x in said if x == "upper hemisphere")
        text += f" ({upper} of the {len(said)} `auto` renders reported the upper hemisphere)"
    return text


def hemisphere_section(ctx):
    L = []
    w = L.append
    w("## The visible hemisphere: `--hemisphere auto` against `full` (N = 128, lloyd)")
    w("")
    w("Issue 14. With a ground no direction below the horizon reaches an object. `auto` (the default, the upper")
    w("hemisphere on every scene here) decomposes only the upper hemisphere: every cell lies above the horizon and all N are")
    w("drawn. `full` decomposes the whole sphere and draws only the cells whose centre is above the horizon, so a cell")
    w("straddling it either lets its light from below shine through the ground or loses its light from above, and which one")
    w("depends on the seed. `sphere_ground` is compared over the sphere's pixels, the others over every object pixel.")
    w("")
    seeds = " / ".join(str(x) for x in HEMISPHERE_SEEDS)
    w(f"| scene / map | auto: seeds {seeds} | auto: best–worst | full: seeds {seeds} | full: best–worst | full: lights drawn |")
    w("| --- | ---: | ---: | ---: | ---: | ---: |")
    for s, m in ctx["hemisphere_pairs"]:
        va, vf = seed_values(ctx, s, m, "auto"), seed_values(ctx, s, m, "full")
        w(f"| {s} / {m} | {' / '.join(cell(x) for x in va)} | {spread(va)} | {' / '.join(cell(x) for x in vf)} | "
          f"{spread(vf)} | {drawn_range(ctx, s, m, 'full')} |")
    w("")
    px = sorted({r["pixels"] for k, r in ctx["study"].results.items() if k in ctx["report_keys"]
                 and k.startswith("sphere_ground|")})
    w("Seed 1 with `auto` is the default case of every other table. On the sphere"
      + (f" ({'/'.join(map(str, px))} pixels)" if px else "")
      + " an error of a few tenths of a percent is the reference's own noise: measured by hand")
    w("with other references of the same settings, that noise alone was 0.18–0.19%, and it differs from one reference to the next.")
    w("Seeds 1–8 on courtyard and studio and that noise analysis: [accuracy/sphere_ground_by_hand.md](accuracy/sphere_ground_by_hand.md).")
    return "\n".join(L)


def regen_command(ctx):
    a = ctx["args"]
    return "scripts/accuracy.py" + (" --full" if a.full else "") + (f" --error {a.error}" if a.error != 0.005 else "")


def shading_default_said(ctx):
    """Where ratio shading loses to cells in the shading table (the commands default to ratio with soft shadows)."""
    worse = []
    for s_, m_ in ctx["shading_pairs"]:
        for n in SHADING_NS:
            c, r = rr(ctx, s_, m_, n=n), rr(ctx, s_, m_, n=n, shading="ratio")
            if c is not None and r is not None and r > c:
                worse.append(f"{s_} / {m_} at N = {n} ({pct(r)} against {pct(c)})")
    said = ("**Default: ratio** (with soft shadows and MSAA 4, the commands' defaults): no dot per cell on glossy "
            "surfaces, at the cost of the prefiltered map at load time.")
    if not worse:
        return said + " It is better on every case above."
    return (f"{said} Ratio is worse on {len(worse)} of {len(ctx['shading_pairs']) * len(SHADING_NS)} cases above, by "
            f"hundredths of a point on diffuse scenes: {'; '.join(worse)}.")


def write_accuracy(ctx, path):
    a, st = ctx["args"], ctx["study"]
    L = []
    w = L.append
    w("# Accuracy of envshadow against the Monte Carlo reference")
    w("")
    w("Generated by `scripts/accuracy.py` (do not edit by hand). Regenerate from a clean build with")
    w("")
    w("    cmake -S . -B build -DENVSHADOW_WERROR=ON && cmake --build build -j2 --target envshadow brdf_figures")
    took = ("rewritten from cached results by --report-only" if a.report_only
            else f"the run that wrote it: {ctx['seconds'] / 60:.0f} min, reusing build/accuracy/")
    w(f"    {regen_command(ctx)}          # this report ({took})")
    w("    scripts/accuracy.py --full   # every scene x map in every study (several hours on this machine)")
    w("    scripts/accuracy.py --from-csv --forget SCENE  # a fresh clone: these results, SCENE's recomputed")
    w("")
    w(f"Machine: {machine_line(ctx)}. Every number below comes from runs of this script on this machine (cached in build/accuracy/).")
    # Only what this report is made of: the cache may hold references and results of other runs.
    timed = st.ref_seconds()
    used_refs = [pr for pr in ctx["report_refs"] if os.path.exists(st.ref_path(*pr))]
    refs = {f"{s}/{m}": timed[os.path.basename(st.ref_path(s, m))] for s, m in used_refs
            if os.path.basename(st.ref_path(s, m)) in timed}
    untimed = len(used_refs) - len(refs)
    used = [st.results[k] for k in ctx["report_keys"] if k in st.results]
    render_total = sum(r["render_s"] for r in used)
    w("")
    timing = (f"{sum(refs.values()) / 60:.0f} min for the {len(refs)} made by this script "
              f"({', '.join(f'{k} {v / 60:.1f}' for k, v in sorted(refs.items()))} min)" if refs else "")
    if untimed:
        timing += ("; " if timing else "") + f"{untimed} made outside this script, their time not recorded here"
    w(f"Compute behind these numbers (summed over the cached steps, wall seconds under load): {len(used_refs)} reference images "
      f"({timing}); {len(used)} renders, {render_total / 60:.0f} min (two at a time, beside the references). From an empty "
      "build/accuracy/ expect roughly the reference total plus 10-20 min (renders overlap the references); the references are cached by scene, map, size and "
      "error target, the results by their settings (`--fresh` forgets the results).")
    w("")
    w("## What is measured")
    w("")
    w("- **Error**: `envshadow compare REF.exr TEST.exr` (relative RMSE over object pixels, docs/DESIGN.md §6) of the")
    w("  real-time image (`envshadow render`, OpenGL through llvmpipe) against `envshadow reference` (Embree,")
    w(f"  importance sampling with MIS, every pixel stopped at a relative standard error of {a.error * 100:g}%). The reference's")
    w("  pixel is the mean over its square by default (`--pixel-filter box`: each Monte Carlo round spreads its")
    w("  camera rays over the pixel, the box filter of `render`'s MSAA resolve, docs/DESIGN.md §5.8), or the value")
    w("  at its centre (`--pixel-filter point`, for renders at `--msaa 1`, one sample at each pixel's centre).")
    w("  The reference noise alone contributes roughly that much to every number (it is a floor, not an error of")
    w("  the method): differences below about 0.5% are not meaningful.")
    w("- **Scenes** (`docs/accuracy/scenes/`, kept out of `assets/scenes/` so the regression suite does not render them):")
    w("  `figure`: a diffuse figure (15k triangles, ρ_d = 0.7) on a diffuse plane, all object pixels compared;")
    w("  `sphere_n10`, `sphere_n100`, `sphere_n1000`: one sphere (ρ_d = 0.1, ρ_s = 0.7, shininess 10 / 100 / 1000, paper Fig. 7) on a plane,")
    w("  **only the sphere's pixels** compared (mask from `sphere_mask.json`); `engine`: `assets/scenes/engine.json`")
    w("  (the 2-cylinder engine, 75k triangles, heavy self-occlusion), all object pixels; `sphere_ground`: a diffuse sphere")
    w("  (r = 0.5 m, ρ_d = 0.7) standing on a 20 m ground (ρ_d = 0.7), only the sphere's pixels compared (`sphere_ground_mask.json`).")
    w("- **Maps**: Blender's `city` (a sun: 6.7% of the importance in one texel), `courtyard` and `studio` (no")
    w("  dominant texel), and `builtin:sky` (analytic sky with a sun); 1024×512 each. `--env` replaces the scene's map.")
    sizes = ", ".join(f"{k} {v[1]}×{v[2]}" for k, v in SCENES.items())
    w(f"- **Sizes** (references and renders): {sizes} pixels; the CPU reference")
    w("  is the bottleneck (one to several minutes each here).")
    w("- **Defaults** unless a row says otherwise: N = 128 cells, method `lloyd`, a shadow budget of N × 256² texels with")
    w("  each cell's tile sized by its share of the light (`--tile-sizes share`, 128² to 1024²), 16-bit depth,")
    w("  2×2 PCF, blended specular with the radiance-weighted cap (`--cap weighted`), diffuse at the cell centre,")
    w("  `--hemisphere auto`: only the upper hemisphere is decomposed when the scene has a ground (docs/DESIGN.md §3.1)"
      + hemisphere_said(ctx) + ".")
    w("- **Methods**: the five load-time decompositions of docs/DESIGN.md §3, and `fs-gpu`: the same Floyd–Steinberg halftoning")
    w("  run every frame on the GPU (geometry shader, docs/FS_GPU.md) over the CPU method's blocks of the importance map")
    w("  (`--fs-importance blocks`), each light the exact integral of its cell, so it is what the dynamic-environment mode")
    w("  costs in accuracy against `fs` on the full 1024×512 map.")
    w("")
    w("Coverage of this run: the N = 128 table on " + ", ".join(f"{s}/{m}" for s, m in ctx["table_pairs"]) + ";")
    w("the full method × N grid on " + ", ".join(f"{s}/{m}" for s, m in ctx["grid_pairs"]) + ";")
    w(f"`--hemisphere auto` against `full` over seeds {HEMISPHERE_SEEDS[0]}–{HEMISPHERE_SEEDS[-1]} on "
      + ", ".join(f"{s}/{m}" for s, m in ctx["hemisphere_pairs"]) + ";")
    w("side studies as listed with each table. `--full` covers every scene × map in every study.")
    if a.no_grid_methods:
        w(f"Methods left out of the grid in this run: {a.no_grid_methods}.")
    w("")

    # ---- targets
    w("## Against the targets (goals, not test thresholds)")
    w("")
    w("| target | measured | met? |")
    w("| --- | --- | --- |")
    for target, measured, met in target_rows(ctx):
        w(f"| {target} | {measured} | {met} |")
    # blended vs single, default (weighted) cap, in images
    bs = []
    for s, m in ctx["spec_pairs"]:
        b, s1 = rr(ctx, s, m, specular="blended", cap="weighted"), rr(ctx, s, m, specular="single", cap="weighted")
        if b is not None and s1 is not None:
            bs.append((s, m, b, s1))
    if bs:
        ok = all(b <= s1 + 0.002 for _, _, b, s1 in bs)
        w("| default cap: blended never worse than single sample (images) | " +
          ", ".join(f"{s}/{m} {pct(b)} vs {pct(s1)}" for s, m, b, s1 in bs) + f" | {'yes' if ok else 'no'} (0.2% slack for reference noise) |")
    f6 = ctx["fig6_summary"]
    for n in (10, 100, 1000):
        mb, xb, ms, xs, worse, cnt = f6[(n, "[0, r]")]
        w(f"| Fig. 6 curves (r = π/8, ψ_c ∈ [0, r]), n = {n}: blended error vs single | mean {pct(mb)} vs {pct(ms)}, max {pct(xb)} vs {pct(xs)}; "
          f"blended worse at {worse} of {cnt} points | mean error {'halved' if mb <= ms / 2 else 'not halved'}; "
          f"{'never worse' if worse == 0 else 'but worse at some ψ_c'} |")
    # lloyd/ccvt vs mediancut/random at equal N
    wins = tot = 0
    losses = []
    for s, m in ctx["grid_pairs"] + [p_ for p_ in ctx["table_pairs"] if p_ not in ctx["grid_pairs"]]:
        for n in NS:
            best = [x for x in (rr(ctx, s, m, "lloyd", n), rr(ctx, s, m, "ccvt", n)) if x is not None]
            base = [x for x in (rr(ctx, s, m, "mediancut", n), rr(ctx, s, m, "random", n)) if x is not None]
            if best and len(base) == 2:
                tot += 1
                if min(best) < min(base):
                    wins += 1
                else:
                    losses.append(f"{s}/{m} N={n}")
    if tot:
        w(f"| equal N: lloyd or ccvt beats mediancut and random | {wins} of {tot} (scene, map, N) cases"
          + (f"; not at {', '.join(losses[:8])}{' …' if len(losses) > 8 else ''}" if losses else "") + f" | {'yes' if wins == tot else 'mostly' if wins >= 0.75 * tot else 'no'} |")
    w("")
    w("For calibration (issue 6): the error of the cell approximation alone (no visibility, 400 random normals, N = 128) was")
    w("lloyd 0.10–0.28%, mediancut 0.32–1.05%, random 0.84–2.1% (diffuse). The image errors below add shadows,")
    w("the cap formula, rasterisation and the reference's own noise.")
    w("")

    # ---- main table
    w("## N = 128, every method")
    w("")
    w("Relative RMSE (a shadow budget of N × 256² texels sized by light, defaults otherwise). Lower is better; the best of each row in bold.")
    w("")
    w("| scene / map | " + " | ".join(METHODS) + " |")
    w("| --- |" + " ---: |" * len(METHODS))
    for s, m in ctx["table_pairs"]:
        vals = [rr(ctx, s, m, meth) for meth in METHODS]
        best = min((v for v in vals if v is not None), default=None)
        w(f"| {s} / {m} | " + " | ".join(("**" + cell(v) + "**") if v is not None and v == best else cell(v) for v in vals) + " |")
    w("")

    # ---- grid
    w("## Error against N")
    w("")
    w("![relative RMSE against N, per method](accuracy/error_vs_n.png)")
    w("")
    for s, m in ctx["grid_pairs"]:
        w(f"**{s} / {m}**")
        w("")
        w("| method | " + " | ".join(f"N = {n}" for n in NS) + " |")
        w("| --- |" + " ---: |" * len(NS))
        for meth in METHODS:
            w(f"| {meth} | " + " | ".join(cell(rr(ctx, s, m, meth, n)) for n in NS) + " |")
        w("")

    # ---- frame time
    bw, bh = ctx["bench_size"]
    w("## Error against frame time")
    w("")
    w(f"Frame time is `envshadow bench` at {bw}×{bh}, a shadow budget of N × 256² texels, median of {a.bench_frames} frames after one warm-up, on **llvmpipe**")
    w("(a CPU rasteriser sharing a loaded 2-core VM: absolute times are hundreds of times a GPU's; the *shape* of the")
    w("trade-off is what carries over, since both the shadow atlas and the shading are linear in N). The per-frame cost")
    w("does not depend on the decomposition method (the same N lights are drawn), so every method's curve uses the")
    w("same time for a given N; the method changes the one-off decomposition time (last column, `lloyd`).")
    w("")
    w("![relative RMSE against frame time](accuracy/error_vs_frame_time.png)")
    w("")
    w("| scene | N | lights drawn | frame ms (median) | shadow atlas ms | shading ms | decompose ms |")
    w("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for scene, b in ctx["bench_rows"].items():
        for row in b["rows"]:
            g = row["gpu_ms"]
            w(f"| {scene} | {row['lights']} | {row['lights_drawn']} | {row['frame_ms']['median']:.0f} | {g['shadow atlas']['median']:.0f} | "
              f"{g['shading']['median']:.0f} | {row.get('decompose_ms', float('nan')):.0f} |")
    w("")

    # ---- side studies
    w("## Specular: blended vs single sample, with each cap radius (N = 128, lloyd)")
    w("")
    w("| scene / map | blended, weighted cap (default) | single, weighted cap | blended, solid-angle cap (paper) | single, solid-angle cap |")
    w("| --- | ---: | ---: | ---: | ---: |")
    for s, m in ctx["spec_pairs"]:
        w(f"| {s} / {m} | {cell(rr(ctx, s, m, specular='blended', cap='weighted'))} | {cell(rr(ctx, s, m, specular='single', cap='weighted'))} | "
          f"{cell(rr(ctx, s, m, specular='blended', cap='solid-angle'))} | {cell(rr(ctx, s, m, specular='single', cap='solid-angle'))} |")
    w("")
    w("(The single-sample value does not use the cap at all, so its two columns differ only by render noise, if at all.)")
    w("")
    w("## Shading: the cells' sum against the ratio estimator (lloyd)")
    w("")
    w("`--shading cells` (the paper's per-cell sum, the default) against `--shading ratio`: the unshadowed reflection")
    w("from the map prefiltered for the BRDF, scaled by the cells' shadowed fraction (docs/DESIGN.md §4.1).")
    w("")
    paired_table(w, ctx["shading_pairs"], SHADING_NS, lambda n: (f"N = {n} cells", f"N = {n} ratio"),
                 lambda s, m, n: (rr(ctx, s, m, n=n), rr(ctx, s, m, n=n, shading="ratio")))
    w("")
    w(shading_default_said(ctx))
    w("")
    w("## Diffuse: cell centre vs cap-integrated (N = 128, lloyd)")
    w("")
    w("| scene / map | centre (paper, default) | cap (exact clamped cosine over the cap) |")
    w("| --- | ---: | ---: |")
    for s, m in ctx["diff_pairs"]:
        w(f"| {s} / {m} | {cell(rr(ctx, s, m, diffuse='center'))} | {cell(rr(ctx, s, m, diffuse='cap'))} |")
    w("")
    w("## Shadow tile size (N = 128, lloyd)")
    w("")
    w("`--tile R` sets the budget, N × R² texels: `uniform` gives every cell R², `share` (the default) sizes each")
    w("cell's tile by its share of the light within that budget (at R = 128 every tile is already the 128² minimum,")
    w("so the two are the same). The hand-measured comparison with `sqrt` sizing: [accuracy/tile_sizes_by_hand.md](accuracy/tile_sizes_by_hand.md).")
    w("")
    paired_table(w, ctx["tile_pairs"], TILES, lambda t: (f"{t}² uniform", f"{t}² share"),
                 lambda s, m, t: (rr(ctx, s, m, tile=t, tile_sizes="uniform"), rr(ctx, s, m, tile=t)))
    w("")
    w("## Seed to seed (N = 128)")
    w("")
    w("`lloyd` and `random` depend on the decomposition seed (`--seed`, default 1); mediancut and fs do not. The spread")
    w("over seeds is the uncertainty of every single-seed entry above.")
    w("")
    w("| scene / map | method | " + " | ".join(f"seed {x}" for x in SEEDS) + " | mediancut | fs |")
    w("| --- | --- |" + " ---: |" * (len(SEEDS) + 2))
    for s, m in ctx["seed_pairs"]:
        for meth in ("lloyd", "random"):
            w(f"| {s} / {m} | {meth} | " + " | ".join(cell(rr(ctx, s, m, meth, seed=x)) for x in SEEDS)
              + f" | {cell(rr(ctx, s, m, 'mediancut'))} | {cell(rr(ctx, s, m, 'fs'))} |")
    w("")
    w(hemisphere_section(ctx))
    w("")
    w("## How the methods spread the energy (N = 128, no rendering)")
    w("")
    w("Share of the map's total luminance carried by the brightest cell and by the eight brightest cells")
    w("(`envshadow decompose --json`), and the decomposition time. A cell is drawn as one direction with one hard")
    w("shadow, so a cell holding several percent of the light turns a soft shadow into a hard one.")
    w("")
    w("| map | method | brightest cell | 8 brightest | decompose s |")
    w("| --- | --- | ---: | ---: | ---: |")
    for (map_, m), d in sorted(ctx["dstats"].items()):
        w(f"| {map_} | {m} | {pct(d['max'])} | {pct(d['top8'])} | {d['seconds']:.1f} |")
    w("")
    w(soft_shadows_section())
    w("")
    w(pixel_filter_section())
    w("")
    w(interiors_section())
    w("")
    w(gltf_section())
    w("")
    w(weaknesses(ctx))
    w("")
    w("All results, including render times, are in [`accuracy/results.csv`](accuracy/results.csv).")
    with atomic_open(path) as f:
        f.write("\n".join(L) + "\n")


def write_paper(ctx, path):
    L = []
    w = L.append
    w("# Reproducing Barsi, Szirmay-Kalos and Szécsi, *Image-Based Illumination on the GPU*")
    w("")
    w(f"Generated by `scripts/accuracy.py` with [ACCURACY.md](ACCURACY.md) (regenerate: `{regen_command(ctx)}`).")
    w(f"Machine: {machine_line(ctx)}.")
    w("")
    w("## Fig. 5: single sample against the exact cap average (ψ_c = 0)")
    w("")
    w("From the C++ twin (`build/tests/brdf/brdf_figures fig5`, data in [`accuracy/fig5.csv`](accuracy/fig5.csv)).")
    w("")
    w("![Fig. 5](accuracy/fig5.png)")
    w("")
    fc = ctx["fig5_cross"]
    w("The ratio passes 2 (an error over 100%) at r_i = " + ", ".join(
        f"{fc[n]:.2f} for n = {n}" if fc[n] else f"(never) for n = {n}" for n in (10, 100, 1000))
      + "; the paper reads 0.6 for n = 10 and 0.18 for n = 100 off its figure.")
    w("")
    w("## Fig. 6: blended and single-sample averages against ψ_c (r = π/8)")
    w("")
    w("From `brdf_figures fig6` ([`accuracy/fig6.csv`](accuracy/fig6.csv)); the plot runs to 2r to show the join at the rim.")
    w("")
    w("![Fig. 6](accuracy/fig6.png)")
    w("")
    w("| n | ψ_c range | blended: mean / max relative error | single: mean / max relative error | points where blended is worse |")
    w("| ---: | --- | --- | --- | ---: |")
    for (n, lim), (mb, xb, ms, xs, worse, cnt) in sorted(ctx["fig6_summary"].items()):
        w(f"| {n} | {lim} | {pct(mb)} / {pct(xb)} | {pct(ms)} / {pct(xs)} | {worse} of {cnt} |")
    w("")
    w("**Check against numerical integration.** The `exact` column is the C++ ring quadrature")
    w("(`tests/brdf/cap_quadrature.h`); this script integrates again independently (midpoint rule, 200 × 200 in")
    w("θ and φ about the cap centre) and, at ψ_c = 0, evaluates the closed form k_s(1 − R^{n+1})/((n+1)(1 − R)).")
    w("It also re-evaluates the blended formula of docs/DESIGN.md §4 in double precision against the C++ twin (float).")
    w("")
    w("| figure | n | r | ψ_c | C++ quadrature | Python quadrature | closed form / blended (Python) | blended (C++) |")
    w("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    worst_q = worst_c = 0.0
    for fig, n, r, psi, exact, mine, closed, bl in ctx["checks"]:
        w(f"| {fig} | {n:g} | {r:.4f} | {psi:.4f} | {exact:.6g} | {mine:.6g} | {closed:.6g} | {bl:.6g} |")
        if exact > 1e-12:
            worst_q = max(worst_q, abs(mine - exact) / exact)
        if fig == "fig5" and exact > 1e-12:
            worst_c = max(worst_c, abs(closed - exact) / exact)
    w("")
    w(f"Largest relative difference, C++ vs Python quadrature: {worst_q * 100:.3g}%; C++ quadrature vs closed form at ψ_c = 0: {worst_c * 100:.3g}%.")
    w("")
    w("## Fig. 7: spheres, single sample (left) and blended (right)")
    w("")
    w("`docs/accuracy/scenes/fig7.json`: shininess 30, 100, 300, 1000 left to right (the paper's spheres are 100), Blender's")
    w("`interior` map (Florence is not available), N = 128, lloyd, radiance-weighted cap; `envshadow render --specular single|blended`.")
    w("As in the paper, the single sample shows each cell as a separate dot in the highlight; the blended average spreads it.")
    w("")
    w("| single sample | blended |")
    w("| --- | --- |")
    w("| ![single](accuracy/fig7_single.png) | ![blended](accuracy/fig7_blended.png) |")
    w("")
    w("Measured against the reference on one sphere (rel. RMSE over the sphere, N = 128): see the specular table in ACCURACY.md.")
    w("")
    e = ctx["fig7_three"]
    w(f"## Fig. 7 three ways: cells, ratio and the reference at N = {FIG7_N}")
    w("")
    w(f"`{FIG7_SCENE}`: the row of `assets/scenes/spheres.json` (ρ_d = 0.25, ρ_s = 0.6, shininess 1, 3, 10, 30, 100, 300")
    w(f"and 1000 from left to right) on a ground under Blender's `interior`, {FIG7_SIZE[0]}×{FIG7_SIZE[1]}, lloyd, N = {FIG7_N},")
    w("one sample per pixel on every side. The paper's per-cell sum (`--shading cells`, blended) shows each cell as a dot")
    w("in the highlights of the glossier spheres; the ratio estimator (`--shading ratio`, docs/DESIGN.md §4.1) takes the")
    w("unshadowed reflection from the prefiltered map and only the shadowing from the cells, so the highlights are the")
    w(f"blurred room, as in the reference (`envshadow reference`, {100 * FIG7_ERROR:g}% standard error per pixel).")
    w(f"Relative RMSE over every object pixel: cells {pct(e['cells'])}, ratio {pct(e['ratio'])}.")
    w("")
    w("| | |")
    w("| --- | --- |")
    w(f"| cells, N = {FIG7_N} | ![cells](accuracy/fig7_cells_n{FIG7_N}.png) |")
    w(f"| ratio, N = {FIG7_N} | ![ratio](accuracy/fig7_ratio_n{FIG7_N}.png) |")
    w("| reference | ![reference](accuracy/fig7_reference.png) |")
    w("")
    w("## Fig. 8: fly-over")
    w("")
    w("`assets/scenes/flyover.json` at t = 0 s and 1.5 s (N = 128): the flying figure's shadow moves across the standing one;")
    w("shadow maps are re-rendered every frame.")
    w("")
    w("| t = 0 s | t = 1.5 s |")
    w("| --- | --- |")
    w("| ![t=0](accuracy/fig8_t0.png) | ![t=1.5](accuracy/fig8_t1.5.png) |")
    w("")
    w("## Table 1: frame rates")
    w("")
    bw, bh = ctx["bench_size"]
    w(f"`envshadow bench --scene assets/scenes/flyover_single.json|flyover.json --sweep lights=64,128 --width {bw} --height {bh}`,")
    w(f"median of {ctx['args'].bench_frames} frames. The paper's resolution is not stated in Table 1; its figures are on a GeForce 6800 GT (2004).")
    w("")
    w("| scene | triangles | N | paper FPS (GeForce 6800 GT) | this machine FPS (llvmpipe, " + f"{bw}×{bh}) | frame ms | shadow atlas ms | shading ms |")
    w("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    paper = {("flyover_single", 64): 33, ("flyover_single", 128): 16.8, ("flyover", 64): 17.8, ("flyover", 128): 7.5}
    names = {"flyover_single": "one figure (paper: one Armadillo, 15k)", "flyover": "two figures (paper: two Armadillos)"}
    for name, b in ctx["table1"].items():
        for row in b["rows"]:
            g = row["gpu_ms"]
            w(f"| {names[name]} | {b.get('triangles', row.get('triangles', '?'))} | {row['lights']} | {paper[(name, row['lights'])]} | "
              f"{row['fps']['median']:.2f} | {row['frame_ms']['median']:.0f} | {g['shadow atlas']['median']:.0f} | {g['shading']['median']:.0f} |")
    w("")
    w("The paper's frame time roughly doubles from 64 to 128 samples (33 → 16.8 FPS) because shadow-map rendering and the")
    w("per-fragment loop are both linear in N; compare the ratio here, not the absolute rate: this machine has no GPU, and with")
    w(f"only {ctx['args'].bench_frames} frames on a shared, loaded machine a single ratio is uncertain (rerun with --bench-frames 20 on an idle machine).")
    with atomic_open(path) as f:
        f.write("\n".join(L) + "\n")


def soft_shadows_section():
    """--shadows hard against soft, measured by hand (docs/accuracy/soft_shadows_by_hand.md): not rerun here."""
    return """## Soft shadows per cell: `--shadows hard` against `soft` (N = 128, lloyd; measured by hand)

Each cell's penumbra from its cap (docs/DESIGN.md §5.9) against the hard 2×2 lookup, everything else at this
report's defaults, same references and pixels (details, commands and a box-on-ground case with its own
reference: [accuracy/soft_shadows_by_hand.md](accuracy/soft_shadows_by_hand.md)):

| scene / map | hard | soft |
| --- | ---: | ---: |
| engine / courtyard | 5.71% | 5.69% |
| figure / studio | 0.845% | 0.769% |
| figure / city | 0.749% | 0.575% |
| sphere_ground / courtyard | 0.314% | 0.314% |
| box_ground / courtyard, N = 64, ground pixels | 1.38% | 1.07% |

No worse anywhere, better where a shadow falls on another surface; `hard` stays the default for its cost
(2.3× the frame on flyover, [PERFORMANCE.md](PERFORMANCE.md)). Not yet part of this script's runs."""


def pixel_filter_section():
    """render and reference at their defaults, measured by hand (docs/accuracy/pixel_filter_by_hand.md)."""
    return """## Pixel filter: `render` and `reference` at their defaults (measured by hand)

`render` at its default `--msaa 4` against `reference` at its default `--pixel-filter box`, and `--msaa 1`
against `--pixel-filter point`, nothing else passed but scene, map, size, N (references at `--error 0.005`);
figures, commands and what is left: [accuracy/pixel_filter_by_hand.md](accuracy/pixel_filter_by_hand.md).
Not yet part of this script's runs."""


def interiors_section():
    """Closed and half-closed scenes, measured by hand (docs/accuracy/interiors_by_hand.md): not rerun here."""
    return """## Closed and half-closed spaces (N = 128, lloyd, ratio + soft; measured by hand)

Three interiors of 0.1 m boxes on the ground (docs/accuracy/scenes/): `room` (a 4 × 4 × 2.5 m room lit through
its door, the camera inside), `room_window` (a window, a table, a cabinet) and `carport` (a roof on pillars).
`--msaa 1 --shading ratio --shadows soft --shadow-rate fragment` (the defaults' shading and shadows) and `--msaa 1` cells +
hard against references through pixel centres at `--error 0.01`; details, commands and causes:
[accuracy/interiors_by_hand.md](accuracy/interiors_by_hand.md).

| scene / map (size) | cells, hard | ratio + soft | ratio + soft ≤ 3% |
| --- | ---: | ---: | --- |
| room / city (128×96) | 13.0% | 4.23% | no |
| room_window / city (64×48) | 1.97% | 1.21% | yes |
| room_window / courtyard (64×48) | 1.54% | 2.04% | yes |
| carport / city (64×48) | 2.08% | 1.63% | yes |
| carport / courtyard (64×48) | 2.18% | 1.65% | yes |

Against the open scenes at the same settings (sphere_ground / courtyard 0.49%, engine / courtyard 1.80%) the
closed room is worse, for two reasons of its own. Light enters through an opening a few cells wide, so each
cell's hard shadow is a whole copy of the door (13% hard); the soft shadows blur the copies. And a wall
running along a cell's direction is hidden under the roof's edge in that cell's depth tile: one depth layer
cannot tell the room from a car port, so the soft filter's taps past the edge read the open air. The soft
shadows' bound (docs/DESIGN.md §5.9, item 7) holds that light back unless the centre of a neighbouring
cell sees the point: the junction lines along the floor and the roof are gone (room 7.80% → 4.23%,
room_window / courtyard 3.18% → 2.04%; the sealed box's brightest pixel 0.0253 → 0.0026), no open scene
moved by more than 0.01 percentage points. What is left in the room is the light through the door: the
patch on the floor, the walls beside the door and a faint line down the far vertical corner. At the
defaults (MSAA 4, the fraction per 2×2 pixels) against a box-filtered reference the room is 3.88% (5.85%
before the bound; the reference's own noise, about 1.4% per pixel, is in the figure); room_window and
carport at 64×48 are 17–30% and 8.5–9.8% there, most of it sunlit patches smaller than a pixel that MSAA
shades once per pixel. Not yet part of this script's runs (the room's reference takes 25 minutes on 2 cores)."""


def gltf_section():
    """glTF's BRDF, measured by hand (docs/accuracy/gltf_by_hand.md): not rerun here."""
    return """## glTF's metallic-roughness BRDF (N = 128, lloyd; measured by hand)

Materials with glTF's parameters in ratio shading (the split sum of docs/DESIGN.md §11) against the reference,
which traces glTF's BRDF itself; details and commands: [accuracy/gltf_by_hand.md](accuracy/gltf_by_hand.md).
`docs/accuracy/scenes/metal_roughness.json` (red plastic and gold over roughness 0.1–0.9 on a ground, city, 192×108):

| | defaults vs box | `--msaa 1` vs point | `--shading cells` (Phong stand-in) vs box |
| --- | ---: | ---: | ---: |
| whole image | 7.99% | 3.18% | 37.9% |
| red plastic spheres (boxes about their centres), roughness 0.3–0.9 | 1.2–1.4% | 0.70–1.0% | 6.9–9.0% |
| gold row | 11.8% | 4.2% | 58.2% |

At the defaults 88% of the squared error is in ten pixels, the roughness-0.1 gold sphere's glint of the sun.
Without shadows (one sphere, 64×64, the sky without its sun): gold at roughness 0.4 3.7%, a red dielectric
0.54%, a roughness-0.05 metal 0.75%; under the white furnace within 0.4% of the albedo. The split sum's own
error grows where the view grazes; a sun in the lobe takes the BRDF's own lobe (docs/DESIGN.md §11, *Compact
lights*): gold under `builtin:sky` 2.4% (7.8% with the split sum alone).
The reference against Cycles ([accuracy/cycles_by_hand.md](accuracy/cycles_by_hand.md), unshadowed spheres):
metals within 0.4% on average, dielectrics 5–7% brighter in Cycles, most of it glTF's Lambert × (1 − F_d)
diffuse against Cycles' Burley. Not yet part of this script's runs.

Alpha MASK: `assets/scenes/leaves.json` (three leaf cards from Blender's glTF exporter over a ground, city,
192×144): 2.0% at the defaults, box reference (`envshadow reference --width 192 --height 144 --error 0.02`),
most of it on the leaves' outlines and midribs; 3.1% before the pre-pass turned alpha into sample coverage.

glTF materials three ways (N = 128; measured by hand): `render` and `reference` at their defaults, and
Blender's Cycles as an independent truth (Blender 3.4.1, direct light only, the ground made 2 km wide so
that it acts as infinite as envshadow's does, at most 1024 samples per pixel, glTF models through Blender's
own importer with alpha MASK as a clip; [accuracy/cycles_by_hand.md](accuracy/cycles_by_hand.md) for the
conventions). Relative RMSE over the reference's object pixels, the ground included:
`scripts/cycles-three-way.sh assets/scenes/SCENE.json OUT WIDTH HEIGHT`.

| scene | size | render vs reference | reference vs Cycles | render vs Cycles |
| --- | --- | ---: | ---: | ---: |
| `leaves.json` (alpha MASK, a diffuse ground) | 192×144 | 1.89% | 1.63% | 2.50% |
| `metal_roughness.json` (glTF's BRDF) | 192×108 | 8.97% | 6.12% | 11.2% |
| `gold_sphere.json` (a metal, roughness 0.3) | 192×144 | 4.02% | 1.96% | 4.56% |

The reference and Cycles agree on the leaves' cut-outs and their shadows and on the gold sphere; on the
red plastic they differ by the dielectric's diffuse gap measured on unshadowed spheres (Cycles' Principled
diffuse is not glTF's Lambert). `render` against either is the method's error, and it lies on the spheres'
reflections of the city's sun. The split sum alone put it in a round lobe about the mirror direction, a
factor n·v below the BRDF's narrower peak: 17.7% on the gold sphere and 20.4% on `metal_roughness.json`
(render against Cycles 17.8% and 26.0%). The sun's cell now takes the BRDF's own lobe (docs/DESIGN.md §11,
*Compact lights*), widened by the pixel's footprint with MSAA, which also spreads the roughness-0.1 gold
sphere's glint over its pixel as the box-filtered reference does. What is left is still the highlights: on
the gold sphere 92% of the squared error is in its worst 1% of pixels, the highlight's shape within a pixel
or two; on `metal_roughness.json` the two pixels of the smoothest gold sphere's glint hold 69% of it (the
reference splits it between them, the render does not quite)."""


def weaknesses(ctx):
    """The plain statements, computed from this run's numbers so they stay true when it is regenerated."""
    L = ["## Where the method is weak", ""]
    w = L.append
    # 1. energy concentration in Lloyd cells
    worst = []
    for s, m in ctx["table_pairs"]:
        vals = {meth: rr(ctx, s, m, meth) for meth in METHODS}
        vals = {k: v for k, v in vals.items() if v is not None}
        if "lloyd" in vals and len(vals) > 1:
            best_m = min(vals, key=vals.get)
            if vals["lloyd"] > 1.5 * vals[best_m]:
                worst.append(f"{s}/{m} (lloyd {pct(vals['lloyd'])}, {best_m} {pct(vals[best_m])})")
    ds = ctx["dstats"]
    if worst:
        extra = ""
        if ("studio", "lloyd") in ds and ("studio", "mediancut") in ds:
            extra = (f" On studio the brightest lloyd cell carries {pct(ds[('studio', 'lloyd')]['max'])} of all the light and the eight "
                     f"brightest {pct(ds[('studio', 'lloyd')]['top8'])}, against {pct(ds[('studio', 'mediancut')]['max'])} / "
                     f"{pct(ds[('studio', 'mediancut')]['top8'])} for mediancut"
                     + (f" and {pct(ds[('studio', 'ccvt')]['max'])} / {pct(ds[('studio', 'ccvt')]['top8'])} for ccvt" if ("studio", "ccvt") in ds else "")
                     + ".")
        spreads = []
        for s_, m_ in ctx["seed_pairs"]:
            v = [x for x in (rr(ctx, s_, m_, "lloyd", seed=x) for x in SEEDS) if x is not None]
            if len(v) > 1:
                spreads.append(f"{s_}/{m_} {pct(min(v))}–{pct(max(v))}")
        w("- **Lloyd under the studio's softboxes.** `lloyd` is clearly worse than the other methods on: " + "; ".join(worst) + "."
          + (f" Over seeds {SEEDS[0]}–{SEEDS[-1]} its error ranges " + ", ".join(spreads) + "," if spreads else "")
          + " so the result depends on where a few strong cells land on the softboxes (most near the horizon), each drawn as")
        w("  one direction with one hard shadow; on the figure the error sits in its self-shadowing." + extra)
        w("  Energy concentration alone does not explain it (fs concentrates about as much and does better here); the cell")
        w("  approximation alone (no visibility) favours lloyd (see the calibration above), so the loss comes with visibility.")
        w("  The cause is not diagnosed further in this report.")
        w("  `ccvt` (equal-energy cells by construction) does better here, at the cost of the slowest decomposition (see the last table).")
    # 2. lights sampled every frame
    gpu = [(rr(ctx, s, m, "fs-gpu"), rr(ctx, s, m, "fs"), s, m) for s, m in ctx["table_pairs"]]
    gpu = [x for x in gpu if x[0] is not None and x[1] is not None]
    if gpu:
        ratios = sorted(g / c for g, c, _, _ in gpu)
        worst_gpu = max(gpu, key=lambda x: x[0] / x[1])
        w(f"- **fs-gpu, the price of no load-time step.** At N = 128 its error is {ratios[0]:.1f}–{ratios[-1]:.1f}× that of `fs` "
          f"(worst {worst_gpu[2]}/{worst_gpu[3]}: {pct(worst_gpu[0])} against {pct(worst_gpu[1])}). Its lights are the GPU")
        w("  scan's samples, each the exact integral of its cell of the importance map (docs/FS_GPU.md), but the scan leaves")
        drawn = [(s, m, ctx["study"].results_for(s, m, "fs-gpu", 128)) for s, m in ctx["table_pairs"]]
        drawn = [f"{r['lights_drawn']} of 128 on {s}/{m}" for s, m, r in drawn if r and "lights_drawn" in r]
        w("  fewer lights than N" + (f" ({', '.join(drawn[:3])})" if drawn else "") + ": glossy surfaces show the gaps between the lights. Use it where the")
        w(f"  environment changes every frame; for a fixed map a load-time method (`fs` here) is up to {ratios[-1]:.1f}× more accurate at the same N.")
    # 3. low N
    lows = [(rr(ctx, s, m, meth, 16), s, m, meth) for s, m in ctx["grid_pairs"] for meth in METHODS if rr(ctx, s, m, meth, 16) is not None]
    if lows:
        mx = max(lows)
        w(f"- **Few cells.** At N = 16 the error reaches {pct(mx[0])} ({mx[1]}/{mx[2]}, {mx[3]}); a glossy sphere needs N ≥ 128 for a few percent.")
    # 3. cap choice
    sa = [(s, m, rr(ctx, s, m, specular="blended", cap="solid-angle"), rr(ctx, s, m, specular="single")) for s, m in ctx["spec_pairs"]]
    sa = [x for x in sa if x[2] is not None and x[3] is not None and x[2] > x[3]]
    weighted = [(s, m, rr(ctx, s, m, specular="blended", cap="weighted"), rr(ctx, s, m, specular="single")) for s, m in ctx["spec_pairs"]]
    weighted_worse = [x for x in weighted if x[2] is not None and x[3] is not None and x[2] > x[3] + 0.002]
    weighted_ok = not weighted_worse  # the same 0.2% slack as the targets row
    if sa:
        w("- **The paper's solid-angle cap.** With `--cap solid-angle` (cos r = 1 − Δω/2π, as in the paper) the blended formula is worse")
        w("  than the single sample it is meant to improve on: " + "; ".join(f"{s}/{m} {pct(b)} vs {pct(x)}" for s, m, b, x in sa)
          + ". The cap smears a light that sits in part of its cell over the whole cell"
          + ("; with the radiance-weighted cap (the default) blended is no worse than the single sample, but the gain over it is "
             "small in these images (see the specular table)." if weighted_ok else
             "; with the radiance-weighted cap (the default) blended is still worse than the single sample on "
             + "; ".join(f"{s}/{m} {pct(b)} vs {pct(x)}" for s, m, b, x in weighted_worse) + " (see the specular table)."))
    f6 = ctx["fig6_summary"]
    if f6[(10, "[0, r]")][4]:
        mb, xb, ms, xs, worse, cnt = f6[(10, "[0, r]")]
        w(f"- **Blended formula at low shininess.** For n = 10 and r = π/8 the blended value overshoots the exact cap average in the middle of")
        w(f"  the cap and is worse than the single sample at {worse} of {cnt} values of ψ_c in [0, r] (max error {pct(xb)} vs {pct(xs)} for the")
        w("  single sample); it is a large improvement only for sharp lobes (n ≥ 100), where the single sample is off by factors.")
    # 4. tile size
    tiles = []
    for s_, m_ in ctx["tile_pairs"]:
        v = [rr(ctx, s_, m_, tile=t) for t in TILES]
        if None not in v:
            tiles.append((max(v) - min(v), s_, m_, v))
    big = [x for x in tiles if x[0] > 0.01]
    small = [x for x in tiles if x[0] <= 0.01]
    if big:
        def against_goal(v):
            at = dict(zip(TILES, v))
            d, top = at.get(DEFAULTS["tile"]), max(TILES)
            text = f"the default {DEFAULTS['tile']}² tiles {'meet' if d <= 0.03 else 'miss'} the 3% goal"
            if d > 0.03 and top > DEFAULTS["tile"]:
                text += (f"; {top}² tiles ({(top // DEFAULTS['tile']) ** 2}× the atlas memory) "
                         + ("reach it" if at[top] <= 0.03 else "help but do not reach it" if at[top] < d else "do not help"))
            return text
        w("- **Shadow-map resolution under heavy occlusion.** Where shadows are small and many, the tile size dominates the error: "
          + "; ".join(f"{s_}/{m_} " + " / ".join(pct(x) for x in v) + f" at {'² / '.join(map(str, TILES))}²: "
                      + against_goal(v) for _, s_, m_, v in big) + ".")
    if small:
        w("- On the open scenes (" + ", ".join(f"{s_}/{m_}" for _, s_, m_, _ in small) + ") the tile size changes the error by at most "
          + pct(max(x[0] for x in small)) + " at these image sizes (about 100 pixels across, too small to show shadow-map aliasing).")
    # 5. the whole sphere on a ground
    bad = []
    for s_, m_ in ctx["hemisphere_pairs"]:
        va = [x for x in seed_values(ctx, s_, m_, "auto") if x is not None]
        vf = [x for x in seed_values(ctx, s_, m_, "full") if x is not None]
        if va and vf and max(vf) > 1.5 * max(va) and max(vf) - max(va) > 0.005:
            bad.append(f"{s_}/{m_} {pct(min(vf))}–{pct(max(vf))} against {pct(min(va))}–{pct(max(va))}")
    if bad:
        w(f"- **The whole sphere over a ground (`--hemisphere full`).** A cell straddling the horizon is kept or dropped whole, by its")
        w(f"  centre, so its light from below shines through the ground or its light from above is lost, and the seed decides")
        w(f"  which: over seeds {HEMISPHERE_SEEDS[0]}–{HEMISPHERE_SEEDS[-1]} " + "; ".join(bad) + " with `auto`. Keep `auto` (the default) wherever a scene has a ground.")
    w(f"- **Reference noise.** References stop at {ctx['args'].error * 100:g}% relative standard error per pixel, so differences between methods")
    w("  under about 0.5% (most of the N ≥ 128 diffuse entries) are not meaningful.")
    w("- **Speed here.** This machine has no GPU: llvmpipe frame times are seconds at N = 128; the trade-off plot shows the")
    w("  shape (cost linear in N), not real-time rates.")
    return "\n".join(L)
