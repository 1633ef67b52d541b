"""The plots (gnuplot) and the paper's figures."""
import csv
import math
import os
import subprocess

from .config import METHODS, NS, ROOT, SCENE_DIR
from .progress import log
from .cache import atomic_open
from .runner import run


def gnuplot(script):
    r = subprocess.run(["gnuplot"], input=script, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError("gnuplot failed:\n" + r.stderr + "\n" + script)


TERM = "set terminal pngcairo size {w},{h} font 'sans,9' noenhanced\n"


def plot_panel(title, series):
    """series: [(name, ['x y', ...])]; methods without points are left out; an empty panel says so."""
    series = [(name, pts) for name, pts in series if pts]
    s = f"set title '{title}'\n"
    if not series:
        return s + ("set label 1 'not covered in this run' at graph 0.5, graph 0.5 center\n"
                    "set xrange [16:256]\nset yrange [0.1:100]\nplot 1/0 notitle\nunset label 1\n"
                    "set autoscale xy\n")
    s += "plot " + ", ".join(f"'-' w lp lw 2 title '{name}'" for name, _ in series) + "\n"
    s += "".join("\n".join(pts) + "\ne\n" for _, pts in series)
    return s


def plot_error_vs_n(study, pairs, path):
    cols = 2
    rows = math.ceil(len(pairs) / cols)
    dat = []
    s = TERM.format(w=900, h=330 * rows) + f"set output '{path}'\nset multiplot layout {rows},{cols}\n"
    s += "set logscale xy\nset xrange [12:340]\nset xtics (16,32,64,128,256)\nset xlabel 'N (cells = lights)'\n"
    s += "set ylabel 'relative RMSE (%)'\nset grid\nset key top right\n"
    for scene, map_ in pairs:
        series = [(m, [f"{n} {100 * study.results_for(scene, map_, m, n)['rel_rmse']}" for n in NS
                       if study.results_for(scene, map_, m, n)]) for m in METHODS]
        s += plot_panel(f"{scene} / {map_}", series)
    s += "unset multiplot\n"
    gnuplot(s)


def plot_error_vs_time(study, pairs, frame_ms, path):
    cols = 2
    rows = math.ceil(len(pairs) / cols)
    s = TERM.format(w=900, h=330 * rows) + f"set output '{path}'\nset multiplot layout {rows},{cols}\n"
    s += "set logscale xy\nset xlabel 'frame time (ms, llvmpipe, see text)'\n"
    s += "set ylabel 'relative RMSE (%)'\nset grid\nset key top right\n"
    for scene, map_ in pairs:
        ft = frame_ms.get(scene)
        if not ft:
            continue
        series = [(m, [f"{ft[n]} {100 * study.results_for(scene, map_, m, n)['rel_rmse']}" for n in NS
                       if n in ft and study.results_for(scene, map_, m, n)]) for m in METHODS]
        s += plot_panel(f"{scene} / {map_}: error against frame time (N = 16 ... 256)", series)
    s += "unset multiplot\n"
    gnuplot(s)


# ---- paper figures ------------------------------------------------------------------------------

def cap_average_numeric(cos_psi_c, r, n, nt=200, nphi=200):
    """Independent check of the C++ quadrature: mean of max(0, w.m)^n over a cap of angular radius r
    whose centre is psi_c from the mirror direction m; midpoint rule in (theta, phi) about the cap centre,
    weight sin(theta), phi over [0, pi] by symmetry."""
    s_c = math.sqrt(max(0.0, 1 - cos_psi_c * cos_psi_c))
    cphi = [math.cos(math.pi * (j + 0.5) / nphi) for j in range(nphi)]
    total = wsum = 0.0
    for i in range(nt):
        th = r * (i + 0.5) / nt
        u, st = math.cos(th), math.sin(th)
        a, b = u * cos_psi_c, st * s_c
        acc = 0.0
        for cp in cphi:
            d = a + b * cp
            if d > 0:
                acc += d ** n
        total += st * acc
        wsum += st * nphi
    return total / wsum


def blended(c, R, n):
    """docs/DESIGN.md §4, written again here only to label the check (the plots use the C++ twin's output)."""
    if c <= R:
        return c ** n
    return (1 - R ** (n + 1)) * (c - R) / ((n + 1) * (1 - R) ** 2) + c ** n * (1 - c) / (1 - R)


def paper_figures(args, outdir):
    fig5 = list(csv.DictReader(run([args.figures, "fig5"]).splitlines()))
    fig6 = list(csv.DictReader(run([args.figures, "fig6"]).splitlines()))
    with atomic_open(f"{outdir}/fig5.csv") as f:
        f.write(run([args.figures, "fig5"]))
    with atomic_open(f"{outdir}/fig6.csv") as f:
        f.write(run([args.figures, "fig6"]))
    # Fig. 5 plot
    s = TERM.format(w=640, h=420) + f"set output '{outdir}/fig5.png'\nset datafile separator ','\n"
    s += "set xlabel 'cell radius r_i (rad)'\nset ylabel 'single sample / exact cap average (psi_c = 0)'\n"
    s += "set logscale y\nset grid\nset key top left\nset xrange [0:pi/2]\nset yrange [1:100]\n"
    s += "set arrow from 0.6, graph 0 to 0.6, graph 1 nohead dt 2\nset arrow from 0.18, graph 0 to 0.18, graph 1 nohead dt 2\n"
    s += "plot " + ", ".join(f"'{outdir}/fig5.csv' every ::1 u ($1=={n}?$2:1/0):6 w l lw 2 title 'n = {n}'"
                             for n in (10, 100, 1000))
    s += ", 2 dt 3 lc rgb 'black' title 'ratio 2 (paper: r = 0.6 at n = 10, 0.18 at n = 100)'\n"
    gnuplot(s)
    # Fig. 6 plot: one panel per n
    s = TERM.format(w=1100, h=360) + f"set output '{outdir}/fig6.png'\nset datafile separator ','\n"
    s += "set multiplot layout 1,3\nset grid\nset xlabel 'psi_c (rad), r = pi/8'\nset ylabel 'average reflectance / k_s'\n"
    s += "set arrow 1 from pi/8, graph 0 to pi/8, graph 1 nohead dt 2\n"
    for n in (10, 100, 1000):
        s += f"set title 'n = {n}'\n"
        if n == 1000:
            s += "set logscale y\nset yrange [1e-4:1]\nset title 'n = 1000 (log scale)'\n"
        s += (f"plot '{outdir}/fig6.csv' every ::1 u ($1=={n}?$3:1/0):4 w l lw 3 lc rgb 'black' title 'exact (quadrature)', "
              f"'' every ::1 u ($1=={n}?$3:1/0):5 w l lw 2 lc rgb 'blue' title 'blended (Barsi)', "
              f"'' every ::1 u ($1=={n}?$3:1/0):6 w l lw 2 dt 2 lc rgb 'red' title 'single sample'\n")
    s += "unset multiplot\n"
    gnuplot(s)

    # Checks: C++ quadrature vs an independent one here, and the closed form at psi_c = 0.
    checks = []
    for row in fig5[::20]:
        n, r, exact = float(row["n"]), float(row["r"]), float(row["exact"])
        mine = cap_average_numeric(1.0, r, n)
        R = math.cos(r)
        closed = (1 - R ** (n + 1)) / ((n + 1) * (1 - R))
        checks.append(("fig5", n, r, 0.0, exact, mine, closed, float(row["blended"])))
    for row in fig6[::32]:
        n, r, psi = float(row["n"]), float(row["r"]), float(row["psi_c"])
        mine = cap_average_numeric(math.cos(psi), r, n)
        checks.append(("fig6", n, r, psi, float(row["exact"]), mine, blended(math.cos(psi), math.cos(r), n),
                       float(row["blended"])))
    # Fig. 6 error summary over psi_c in [0, r] (the paper's range) and [0, 2r]
    summary = {}
    for n in (10, 100, 1000):
        rows = [r for r in fig6 if float(r["n"]) == n]
        for lim_name, lim in (("[0, r]", 1.0), ("[0, 2r]", 2.0)):
            sel = [r for r in rows if float(r["psi_c"]) <= lim * float(r["r"]) + 1e-9]
            eb = [abs(float(r["blended"]) - float(r["exact"])) / float(r["exact"]) for r in sel]
            es = [abs(float(r["single"]) - float(r["exact"])) / float(r["exact"]) for r in sel]
            worse = sum(1 for b, s_ in zip(eb, es) if b > s_ + 1e-6)
            summary[(n, lim_name)] = (sum(eb) / len(eb), max(eb), sum(es) / len(es), max(es), worse, len(sel))
    fig5_ratio = {}
    for n in (10, 100, 1000):
        rows = [r for r in fig5 if float(r["n"]) == n]
        cross = next((float(r["r"]) for r in rows if float(r["single_over_exact"]) > 2.0), None)
        fig5_ratio[n] = cross
    return checks, summary, fig5_ratio


FIG7_SCENE = f"{SCENE_DIR}/fig7_shininess.json"
FIG7_SIZE = (640, 160)
FIG7_N = 32
FIG7_ERROR = 0.01  # a picture to look at: 1% noise per pixel is invisible after tone mapping


def fig7_three_ways(args, study, outdir):
    """Issue 15's Fig. 7 three ways: the spheres of shininess 1 ... 1000 in cells and ratio shading at N = 32 and the
    reference, as PNGs, with each mode's relative RMSE over every object pixel. Returns {mode: rel_rmse}."""
    w, h = map(str, FIG7_SIZE)
    ref = f"{study.cache}/ref/fig7_shininess__{w}x{h}__e{FIG7_ERROR}__point.exr"
    if not os.path.exists(ref) or not os.path.exists(f"{outdir}/fig7_reference.png"):
        log(f"reference fig7_shininess {w}x{h} error {FIG7_ERROR} ...")
        run([args.bin, "reference", "--scene", FIG7_SCENE, "--width", w, "--height", h, "--error", str(FIG7_ERROR),
             "--pixel-filter", "point", "--exr", ref + ".tmp.exr", "--png", f"{outdir}/fig7_reference.png"])
        os.replace(ref + ".tmp.exr", ref)
    errors = {}
    for mode in ("cells", "ratio"):
        img = f"{study.cache}/img/fig7_{mode}.exr"
        run([args.bin, "render", "--scene", FIG7_SCENE, "--width", w, "--height", h, "--lights", str(FIG7_N),
             # One sample per pixel centre, as the reference's one ray per pixel centre.
             "--shading", mode, "--shadows", "hard", "--msaa", "1", "--exr", img, "--out", f"{outdir}/fig7_{mode}_n{FIG7_N}.png"])
        vals = dict(kv.split("=") for kv in run([args.bin, "compare", ref, img]).split())
        errors[mode] = float(vals["rel_rmse"])
    return errors
