#!/usr/bin/env python3
"""Accuracy report: writes docs/ACCURACY.md, docs/PAPER.md and the plots in docs/accuracy/.

    scripts/accuracy.py            # the committed report (a subset of scenes x maps, see COVERAGE)
    scripts/accuracy.py --full     # every scene x map, every method x N (hours on a loaded 2-core VM)
    scripts/accuracy.py --self-test  # the cache keys and the issue-14 target rows on made-up results
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
import contextlib
import csv
import io
import json
import math
import os
import platform
import re
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORLD = "/usr/share/blender/datafiles/studiolights/world"
SCENE_DIR = "docs/accuracy/scenes"

# scene name -> (file, reference width, height, mask scene or None). The sphere scenes are compared over
# the sphere only (a mask rendered from sphere_mask.json / sphere_ground_mask.json), the others over every
# object pixel.
SCENES = {
    "figure": (f"{SCENE_DIR}/figure.json", 128, 72, None),
    "sphere_n10": (f"{SCENE_DIR}/sphere_n10.json", 96, 72, f"{SCENE_DIR}/sphere_mask.json"),
    "sphere_n100": (f"{SCENE_DIR}/sphere_n100.json", 96, 72, f"{SCENE_DIR}/sphere_mask.json"),
    "sphere_n1000": (f"{SCENE_DIR}/sphere_n1000.json", 96, 72, f"{SCENE_DIR}/sphere_mask.json"),
    "engine": ("assets/scenes/engine.json", 128, 72, None),
    "sphere_ground": (f"{SCENE_DIR}/sphere_ground.json", 160, 120, f"{SCENE_DIR}/sphere_ground_mask.json"),
}
MAPS = {"city": f"{WORLD}/city.exr", "courtyard": f"{WORLD}/courtyard.exr", "studio": f"{WORLD}/studio.exr",
        "sky": "builtin:sky"}
METHODS = ["lloyd", "ccvt", "mediancut", "random", "fs", "fs-gpu"]
DECOMPOSE_METHODS = [m for m in METHODS if m != "fs-gpu"]  # fs-gpu samples every frame: no `decompose` step
NS = [16, 32, 64, 128, 256]
TILES = [128, 256, 512]
SHADING_NS = NS  # the shading study: cells against ratio, N = 16 ... 256 (issue 15)
# hemisphere "auto": the upper hemisphere when the scene has a ground (every scene here has one), else the whole sphere.
# tile_sizes "share": a budget of N x tile^2 texels, each cell's tile sized by its share of the light (issue 14 part 3).
DEFAULTS = {"tile": 256, "specular": "blended", "cap": "weighted", "diffuse": "center", "seed": 1, "hemisphere": "auto",
            "tile_sizes": "share", "shading": "cells"}

# What the default run covers. --full: every scene x map in every study.
GRID_PAIRS = [("figure", "city"), ("figure", "studio"), ("sphere_n100", "city"), ("sphere_n100", "studio")]
TABLE_PAIRS = GRID_PAIRS + [("sphere_n10", "city"), ("engine", "courtyard"), ("sphere_n100", "sky")]
SPECULAR_PAIRS = [("sphere_n10", "city"), ("sphere_n100", "city"), ("sphere_n100", "studio")]
DIFFUSE_PAIRS = [("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]
# The shading study (issue 15): cells against ratio, glossy and diffuse.
SHADING_PAIRS = [("sphere_n10", "city"), ("sphere_n100", "city"), ("sphere_n100", "studio"), ("sphere_n100", "sky"),
                 ("sphere_n1000", "city"), ("sphere_n1000", "studio"), ("sphere_n1000", "sky"),
                 ("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]
TILE_PAIRS = [("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]

# The seed study: the same scene decomposed with other seeds (lloyd and random use one; mediancut and fs do not).
SEED_PAIRS = [("figure", "studio"), ("sphere_n100", "studio"), ("figure", "city")]
SEEDS = [1, 2, 3]

# The hemisphere study (issue 14): --hemisphere auto (the default; the upper hemisphere on these scenes) against
# --hemisphere full (the whole sphere decomposed, the cells whose centre is below the horizon dropped), lloyd N = 128.
GROUND_PAIRS = [("sphere_ground", "city"), ("sphere_ground", "courtyard"), ("sphere_ground", "studio")]
HEMISPHERE_PAIRS = GROUND_PAIRS + [("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]
HEMISPHERES = ["auto", "full"]
HEMISPHERE_SEEDS = [1, 2, 3, 4]

lock = threading.Lock()


def wait_for_lock(path):
    """Another process (pid in the file) is making this reference: wait for it rather than start a second one."""
    said = False
    while os.path.exists(path):
        try:
            with open(path) as f:
                os.kill(int(f.read().strip()), 0)
        except (ValueError, OSError):
            os.remove(path)  # stale: its process is gone
            return
        if not said:
            log(f"waiting for {os.path.basename(path)} (another process is making it) ...")
            said = True
        time.sleep(10)


def result_key(scene, map_, method, n, o, error):
    """Keys written before --hemisphere and --tile-sizes existed have neither part: those renders were of the full
    sphere with uniform tiles."""
    w, h = SCENES[scene][1:3]
    seed = "" if o["seed"] == 1 else f"|seed{o['seed']}"
    hemisphere = "" if o["hemisphere"] == "full" else f"|hemisphere-{o['hemisphere']}"
    tiles = "" if o["tile_sizes"] == "uniform" else f"|tiles-{o['tile_sizes']}"
    shading = "" if o["shading"] == "cells" else f"|shading-{o['shading']}"
    return (f"{scene}|{map_}|{method}|{n}|{o['tile']}|{o['specular']}|{o['cap']}|{o['diffuse']}|{w}x{h}|{error}"
            f"{seed}{hemisphere}{tiles}{shading}")


def key_fields(key):
    """The CSV columns of a result key: the ten fixed parts, then seed, hemisphere and tile sizes (defaults when
    absent)."""
    parts = key.split("|")
    seed, hemisphere, tiles, shading = "1", "full", "uniform", "cells"
    for extra in parts[10:]:
        if extra.startswith("seed"):
            seed = extra[4:]
        elif extra.startswith("hemisphere-"):
            hemisphere = extra[len("hemisphere-"):]
        elif extra.startswith("tiles-"):
            tiles = extra[len("tiles-"):]
        elif extra.startswith("shading-"):
            shading = extra[len("shading-"):]
    return parts[:10] + [seed, hemisphere, tiles, shading]


class Progress:
    """One updating line on a terminal (stderr): cases done, elapsed, an estimate of what is left. Nothing
    when stderr is not a terminal, so logs stay clean; log() clears it and draws it again under each message."""

    def __init__(self, total, stream=None, clock=time.time):
        self.stream = stream or sys.stderr
        self.on = total > 0 and self.stream.isatty()
        self.total, self.done, self.clock, self.start = total, 0, clock, clock()

    def text(self):
        elapsed = self.clock() - self.start
        words = f"{self.done}/{self.total} cases, {clock_words(elapsed)} elapsed"
        if 0 < self.done < self.total:
            words += f", about {clock_words(elapsed / self.done * (self.total - self.done))} left"
        return words

    def draw(self):
        if self.on:
            self.stream.write("\r\033[K" + self.text())
            self.stream.flush()

    def clear(self):
        if self.on:
            self.stream.write("\r\033[K")
            self.stream.flush()

    def step(self):
        with lock:
            self.done += 1
            self.draw()

    def finish(self):
        with lock:
            self.clear()
            self.on = False


def clock_words(seconds):
    m, s = divmod(int(round(seconds)), 60)
    return f"{m // 60}:{m % 60:02d}:{s:02d}" if m >= 60 else f"{m}:{s:02d}"


progress = Progress(0)


@contextlib.contextmanager
def atomic_open(path):
    """Writes `path` whole or not at all (an interrupted run leaves the previous file): a temporary beside it,
    renamed over it once written."""
    tmp = path + ".tmp"
    try:
        with open(tmp, "w") as f:
            yield f
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def log(msg):
    with lock:
        progress.clear()
        print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)
        progress.draw()


def run(cmd, **kw):
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return r.stdout


class Study:
    def __init__(self, args):
        self.a = args
        self.cache = os.path.join(ROOT, args.cache)
        os.makedirs(f"{self.cache}/ref", exist_ok=True)
        os.makedirs(f"{self.cache}/img", exist_ok=True)
        self.results_path = f"{self.cache}/results.json"
        self.results = {}
        if os.path.exists(self.results_path) and not args.fresh:
            with open(self.results_path) as f:
                self.results = json.load(f)
        self.ref_ready = {}

    def import_csv(self, path):
        """Starts the cache from the committed results (docs/accuracy/results.csv): a fresh clone then renders
        only what is missing, and makes only those results' references."""
        added = 0
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                o = dict(tile=int(row["tile"]), specular=row["specular"], cap=row["cap"], diffuse=row["diffuse"],
                         seed=int(row["seed"]), hemisphere=row["hemisphere"], tile_sizes=row["tile_sizes"],
                         shading=row["shading"])
                key = result_key(row["scene"], row["map"], row["method"], int(row["N"]), o, float(row["ref_error"]))
                if key in self.results or row["size"] != "x".join(map(str, SCENES[row["scene"]][1:3])):
                    continue
                r = {"rel_rmse": float(row["rel_rmse"]), "psnr": float(row["psnr"]), "pixels": int(row["pixels"]),
                     "render_s": float(row["render_s"])}
                if row["hemisphere_used"]:
                    r["hemisphere_used"] = row["hemisphere_used"]
                if row["lights_drawn"]:
                    r["lights_drawn"] = int(row["lights_drawn"])
                self.results[key] = r
                added += 1
        self.save()
        log(f"{added} results taken from {path}")

    def forget(self, scenes):
        """Drops the cached results and references of these scenes (after a change that moves their images)."""
        with lock:
            for key in [k for k in self.results if k.split("|")[0] in scenes]:
                del self.results[key]
        self.save()
        for scene in scenes:
            for map_ in MAPS:
                with contextlib.suppress(FileNotFoundError):
                    os.remove(self.ref_path(scene, map_))

    def save(self):
        with lock:
            with open(self.results_path + ".tmp", "w") as f:
                json.dump(self.results, f, indent=0, sort_keys=True)
            os.replace(self.results_path + ".tmp", self.results_path)

    def ref_path(self, scene, map_):
        _, w, h, _ = SCENES[scene]
        return f"{self.cache}/ref/{scene}__{map_}__{w}x{h}__e{self.a.error}.exr"

    def make_references(self, pairs):
        """Runs in its own thread: one reference at a time, in the order given; renders wait per pair."""
        for scene, map_ in pairs:
            out = self.ref_path(scene, map_)
            wait_for_lock(out + ".lock")
            if not os.path.exists(out):
                with open(out + ".lock", "w") as f:
                    f.write(str(os.getpid()))
                f, w, h, _ = SCENES[scene]
                log(f"reference {scene} {map_} {w}x{h} error {self.a.error} ...")
                t = time.time()
                try:
                    run([self.a.bin, "reference", "--scene", f, "--env", MAPS[map_], "--width", str(w), "--height",
                         str(h), "--error", str(self.a.error), "--exr", out + ".tmp.exr"])
                    os.replace(out + ".tmp.exr", out)
                    log(f"reference {scene} {map_} took {time.time() - t:.0f} s")
                    self.record_ref_seconds(os.path.basename(out), time.time() - t)
                except RuntimeError as e:
                    log(f"reference {scene} {map_} FAILED: {e}")
                finally:
                    os.remove(out + ".lock")
            self.ref_ready.setdefault((scene, map_), threading.Event()).set()

    def record_ref_seconds(self, name, seconds):
        path = f"{self.cache}/ref/seconds.json"
        with lock:
            d = json.load(open(path)) if os.path.exists(path) else {}
            d[name] = seconds
            with atomic_open(path) as f:
                json.dump(d, f, indent=0)

    def ref_seconds(self):
        path = f"{self.cache}/ref/seconds.json"
        return json.load(open(path)) if os.path.exists(path) else {}

    def reference(self, scene, map_):
        with lock:
            ev = self.ref_ready.setdefault((scene, map_), threading.Event())
        ev.wait()
        out = self.ref_path(scene, map_)
        if not os.path.exists(out):
            raise RuntimeError(f"no reference for {scene} {map_}")
        return out

    def mask(self, scene):
        f, w, h, mask_scene = SCENES[scene]
        if not mask_scene:
            return None
        out = f"{self.cache}/ref/mask__{os.path.basename(mask_scene)}__{w}x{h}.png"
        with lock:
            if not os.path.exists(out):
                run([self.a.bin, "render", "--scene", mask_scene, "--width", str(w), "--height", str(h),
                     "--no-background", "--lights", "16", "--msaa", "1", "--out", out])
        return out

    def measure(self, scene, map_, method="lloyd", n=128, **opts):
        o = dict(DEFAULTS, **opts)
        f, w, h, _ = SCENES[scene]
        key = result_key(scene, map_, method, n, o, self.a.error)
        if key in self.results:
            return self.results[key]
        mask = self.mask(scene)
        img = f"{self.cache}/img/{key.replace('|', '_')}.exr"
        t = time.time()
        said = run([self.a.bin, "render", "--scene", f, "--env", MAPS[map_], "--lights", str(n), "--method", method,
             "--width", str(w), "--height", str(h), "--tile", str(o["tile"]), "--specular", o["specular"],
             "--cap", o["cap"], "--diffuse", o["diffuse"], "--seed", str(o["seed"]), "--hemisphere", o["hemisphere"],
             "--tile-sizes", o["tile_sizes"], "--shading", o["shading"],
             # One sample at each pixel's centre, as the reference's one ray per pixel centre.
             "--msaa", "1", "--exr", img])
        seconds = time.time() - t
        ref = self.reference(scene, map_)  # after the render: renders run ahead of the references
        cmd = [self.a.bin, "compare", ref, img] + (["--mask", mask] if mask else [])
        out = run(cmd)
        vals = dict(kv.split("=") for kv in out.split())
        r = {"rel_rmse": float(vals["rel_rmse"]), "psnr": float(vals["psnr"]), "pixels": int(vals["pixels"]),
             "render_s": seconds}
        # What the render says it decomposed ("upper hemisphere" / "full sphere") and how many lights it drew.
        used = re.search(r"(upper hemisphere|full sphere)", said)
        drawn = re.search(r"lights: (\d+) drawn", said)
        if used:
            r["hemisphere_used"] = used.group(1)
        if drawn:
            r["lights_drawn"] = int(drawn.group(1))
        os.remove(img)
        with lock:
            self.results[key] = r
        self.save()
        log(f"{key}: rel_rmse {r['rel_rmse'] * 100:.2f}%  ({seconds:.1f} s)")
        progress.step()
        return r


def pct(x):
    return f"{100 * x:.2f}%"


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
    ref = f"{study.cache}/ref/fig7_shininess__{w}x{h}__e{FIG7_ERROR}.exr"
    if not os.path.exists(ref) or not os.path.exists(f"{outdir}/fig7_reference.png"):
        log(f"reference fig7_shininess {w}x{h} error {FIG7_ERROR} ...")
        run([args.bin, "reference", "--scene", FIG7_SCENE, "--width", w, "--height", h, "--error", str(FIG7_ERROR),
             "--exr", ref + ".tmp.exr", "--png", f"{outdir}/fig7_reference.png"])
        os.replace(ref + ".tmp.exr", ref)
    errors = {}
    for mode in ("cells", "ratio"):
        img = f"{study.cache}/img/fig7_{mode}.exr"
        run([args.bin, "render", "--scene", FIG7_SCENE, "--width", w, "--height", h, "--lights", str(FIG7_N),
             # One sample per pixel centre, as the reference's one ray per pixel centre.
             "--shading", mode, "--msaa", "1", "--exr", img, "--out", f"{outdir}/fig7_{mode}_n{FIG7_N}.png"])
        vals = dict(kv.split("=") for kv in run([args.bin, "compare", ref, img]).split())
        errors[mode] = float(vals["rel_rmse"])
    return errors


# ---- benches ------------------------------------------------------------------------------------

def bench(args, cache, scene, sweep, width, height, frames, name):
    out = f"{cache}/bench_{name}_{width}x{height}_f{frames}.json"
    if not os.path.exists(out):
        log(f"bench {scene} {sweep} ...")
        # The shadow cache off: every timed frame draws the atlas, as a scene with anything moving does (a
        # still scene's frames after the first draw none, docs/DESIGN.md §5.11).
        run([args.bin, "bench", "--scene", scene, "--width", str(width), "--height", str(height), "--frames",
             str(frames), "--warmup", "1", "--sweep", sweep, "--variants", "shadow_cache=off", "--json",
             out + ".tmp.json"])
        os.replace(out + ".tmp.json", out)
    with open(out) as f:
        return json.load(f)


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


def rr(ctx, scene, map_, m="lloyd", n=128, **o):
    r = ctx["study"].results_for(scene, map_, m, n, **o)
    return r["rel_rmse"] if r else None


def paired_table(w, pairs, values, headings, results):
    """A table with two columns (headings(v), results(scene, map, v)) for each of `values`, a row per pair."""
    w("| scene / map | " + " | ".join(" | ".join(headings(v)) for v in values) + " |")
    w("| --- |" + " ---: |" * (2 * len(values)))
    for s, m in pairs:
        w(f"| {s} / {m} | " + " | ".join(" | ".join(cell(x) for x in results(s, m, v)) for v in values) + " |")


def cell(x):
    return "–" if x is None else pct(x)


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


def seed_values(ctx, scene, map_, hemisphere):
    return [rr(ctx, scene, map_, seed=x, hemisphere=hemisphere) for x in HEMISPHERE_SEEDS]


def spread(vals):
    """'best–worst (worst/best ×)' over the measured seeds."""
    v = [x for x in vals if x is not None]
    if not v:
        return "–"
    return f"{pct(min(v))}–{pct(max(v))} ({max(v) / min(v):.2f}×)" if min(v) > 0 else f"{pct(min(v))}–{pct(max(v))}"


def drawn_range(ctx, scene, map_, hemisphere):
    st = ctx["study"]
    d = []
    for x in HEMISPHERE_SEEDS:
        r = st.results_for(scene, map_, "lloyd", 128, seed=x, hemisphere=hemisphere)
        if r and "lights_drawn" in r:
            d.append(r["lights_drawn"])
    if not d:
        return "–"
    return f"{min(d)} of 128" if min(d) == max(d) else f"{min(d)}–{max(d)} of 128"


def issue14_targets(ctx):
    """Issue 14's rows of the targets table: (target, measured, met) from this run's numbers."""
    rows = []
    pairs = set(ctx["hemisphere_pairs"])
    for (s, m), goal in ((("engine", "courtyard"), 0.03), (("figure", "studio"), 0.015)):
        v = [x for x in seed_values(ctx, s, m, "auto") if x is not None] if (s, m) in pairs else []
        one = rr(ctx, s, m)
        if one is None:
            continue
        measured = f"{pct(one)} (seed 1)" + (f"; seeds {HEMISPHERE_SEEDS[0]}–{HEMISPHERE_SEEDS[-1]}: worst {pct(max(v))}"
                                             if len(v) > 1 else "")
        worst = max(v) if len(v) > 1 else one
        met = "yes" if worst <= goal else ("at seed 1 only" if one <= goal else "no")
        rows.append((f"issue 14: {s}/{m}, N = 128, default texel budget (128 tiles of 256²): rel. RMSE ≤ {100 * goal:g}%",
                     measured, met))
    ground = [(m, [x for x in seed_values(ctx, s, m, "auto") if x is not None]) for s, m in ctx["hemisphere_pairs"]
              if s == "sphere_ground"]
    ground = [(m, v) for m, v in ground if v]
    if ground:
        ok = all(max(v) <= 0.01 for _, v in ground)
        rows.append((f"issue 14: diffuse sphere on a ground, N = 128, every map, worst of seeds {HEMISPHERE_SEEDS[0]}–{HEMISPHERE_SEEDS[-1]}: rel. RMSE ≤ 1%",
                     ", ".join(f"{m} {pct(max(v))}" for m, v in ground)
                     + ("" if len(ground) == 3 else f" (only {len(ground)} of city, courtyard, studio measured)"),
                     "yes" if ok and len(ground) == 3 else "no"))
        stable = [(m, v) for m, v in ground if m in ("courtyard", "studio")]
        if stable:
            ok = all(max(v) <= 0.015 and (max(v) <= 1.5 * min(v) or max(v) - min(v) <= 0.005) for _, v in stable)
            rows.append((f"issue 14: the same, courtyard and studio: every seed ≤ 1.5%, worst ≤ 1.5× best or within 0.5 points",
                         ", ".join(f"{m} {spread(v)}" for m, v in stable), "yes" if ok else "no"))
    return rows


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


def issue15_targets(ctx):
    """Issue 15's rows: the glossy sphere in ratio shading already at N = 32, n = 100 within 2% and n = 1000
    within 3%, on city, studio and sky."""
    rows = []
    for scene, goal in (("sphere_n100", 0.02), ("sphere_n1000", 0.03)):
        vals = [(m, rr(ctx, scene, m, n=32, shading="ratio")) for m in ("city", "studio", "sky")
                if (scene, m) in set(ctx["shading_pairs"])]
        vals = [(m, v) for m, v in vals if v is not None]
        if not vals:
            continue
        ok = len(vals) == 3 and all(v <= goal for _, v in vals)
        rows.append((f"issue 15: {scene}, `--shading ratio`, N = 32: rel. RMSE ≤ {100 * goal:g}% on city, studio and sky",
                     ", ".join(f"{m} {pct(v)}" for m, v in vals), "yes" if ok else "no"))
    return rows


def shading_default_said(ctx):
    """Issue 15: ratio becomes the default only if it is better on every case of the shading table."""
    worse = []
    for s_, m_ in ctx["shading_pairs"]:
        for n in SHADING_NS:
            c, r = rr(ctx, s_, m_, n=n), rr(ctx, s_, m_, n=n, shading="ratio")
            if c is not None and r is not None and r > c:
                worse.append(f"{s_} / {m_} at N = {n} ({pct(r)} against {pct(c)})")
    if not worse:
        return "**Default:** ratio is better on every case above."
    return (f"**Default: cells stays** (issue 15 asks for ratio only where it is better on every case). Ratio is "
            f"worse on {len(worse)} of {len(ctx['shading_pairs']) * len(SHADING_NS)}: {'; '.join(worse)}; it is also "
            f"the one that needs the prefiltered map at load time. Where the surfaces are glossy, `--shading ratio` "
            f"is the better choice at any N.")


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
    w(f"  importance sampling with MIS, every pixel stopped at a relative standard error of {a.error * 100:g}%).")
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
    diff_vals = [(s, m, rr(ctx, s, m)) for s, m in ctx["table_pairs"] if s in ("figure", "engine")]
    diff_vals = [v for v in diff_vals if v[2] is not None]
    if diff_vals:
        worst = max(diff_vals, key=lambda v: v[2])
        ok = all(v[2] <= 0.03 for v in diff_vals)
        w(f"| diffuse scenes, N = 128, a 128 × 256² shadow budget: rel. RMSE ≤ 3% | " + ", ".join(f"{s}/{m} {pct(v)}" for s, m, v in diff_vals)
          + f" | {'yes' if ok else 'no: worst ' + worst[0] + '/' + worst[1] + ' ' + pct(worst[2])} |")
    sh_vals = [(s, m, rr(ctx, s, m)) for s, m in ctx["table_pairs"] if s == "sphere_n100"]
    sh_vals = [v for v in sh_vals if v[2] is not None]
    if sh_vals:
        ok = all(v[2] <= 0.06 for v in sh_vals)
        w(f"| shininess 100, N = 128: rel. RMSE ≤ 6% | " + ", ".join(f"{m} {pct(v)}" for s, m, v in sh_vals)
          + f" | {'yes' if ok else 'no'} |")
    for target, measured, met in issue14_targets(ctx) + issue15_targets(ctx):
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

def decomposition_stats(args, cache, maps=("city", "studio"), n=128):
    """Largest cell's share of the map's total luminance, per method (decompose --json, cached)."""
    os.makedirs(f"{cache}/decomp", exist_ok=True)
    out = {}
    for map_ in maps:
        for m in DECOMPOSE_METHODS:
            path = f"{cache}/decomp/{map_}__{m}__{n}.json"
            if args.report_only and not os.path.exists(path):
                continue
            if not os.path.exists(path):
                log(f"decompose {map_} {m} {n} ...")
                run([args.bin, "decompose", "--env", MAPS[map_], "--lights", str(n), "--method", m, "--json",
                     path + ".tmp.json"])
                os.replace(path + ".tmp.json", path)
            with open(path) as f:
                d = json.load(f)
            lum = [0.2126 * l["radiance"][0] + 0.7152 * l["radiance"][1] + 0.0722 * l["radiance"][2] for l in d["lights"]]
            tot = sum(lum)
            top = sorted(lum, reverse=True)
            out[(map_, m)] = {"max": top[0] / tot, "top8": sum(top[:8]) / tot, "seconds": d.get("seconds", float("nan"))}
    return out


def self_test():
    """The cache keys and the issue-14 target rows on made-up results (no build needed); 0 when all hold."""
    faults = []
    o = dict(DEFAULTS)
    full, auto = result_key("figure", "city", "lloyd", 128, dict(o, hemisphere="full"), 0.005), result_key(
        "figure", "city", "lloyd", 128, o, 0.005)
    if full == auto:
        faults.append("auto and full share a cache key")
    old = result_key("figure", "city", "lloyd", 128, dict(o, hemisphere="full", tile_sizes="uniform"), 0.005)
    if old != "figure|city|lloyd|128|256|blended|weighted|center|128x72|0.005":
        faults.append(f"a full-sphere, uniform-tile key is not the key written before --hemisphere: {old}")
    if old in (full, auto):
        faults.append("uniform and share tiles share a cache key")
    if key_fields(full)[10:] != ["1", "full", "share", "cells"] or key_fields(auto)[10:] != ["1", "auto", "share", "cells"]:
        faults.append(f"key fields: {key_fields(full)}, {key_fields(auto)}")
    if key_fields(old)[10:] != ["1", "full", "uniform", "cells"]:
        faults.append(f"key fields of {old}: {key_fields(old)}")
    ratio = result_key("figure", "city", "lloyd", 128, dict(o, shading="ratio"), 0.005)
    if ratio == auto or key_fields(ratio)[10:] != ["1", "auto", "share", "ratio"]:
        faults.append(f"the ratio-shading key: {ratio}")
    seeded = result_key("sphere_ground", "studio", "lloyd", 128, dict(o, seed=3), 0.005)
    if key_fields(seeded)[10:] != ["3", "auto", "share", "cells"]:
        faults.append(f"key fields of {seeded}: {key_fields(seeded)}")

    # Made-up results: the engine misses its 3% at seed 2 only, the figure meets 1.5%, the sphere misses 1% on city.
    results = {}
    def put(scene, map_, seed, value):
        results[result_key(scene, map_, "lloyd", 128, dict(o, seed=seed), 0.005)] = {"rel_rmse": value}
    for x in HEMISPHERE_SEEDS:
        put("engine", "courtyard", x, 0.04 if x == 2 else 0.02)
        put("figure", "studio", x, 0.01)
        put("sphere_ground", "city", x, 0.012)
        put("sphere_ground", "courtyard", x, 0.003)
        put("sphere_ground", "studio", x, 0.003 + 0.001 * x)
    study = argparse.Namespace(results_for=lambda s_, m_, meth, n, **kw: results.get(
        result_key(s_, m_, meth, n, dict(DEFAULTS, **kw), 0.005)))
    rows = issue14_targets({"study": study, "hemisphere_pairs": HEMISPHERE_PAIRS})
    met = {r[0].split(":")[1].split(",")[0].strip(): r[2] for r in rows}
    want = {"engine/courtyard": "at seed 1 only", "figure/studio": "yes", "diffuse sphere on a ground": "no",
            "the same": "yes"}
    if met != want:
        faults.append(f"issue-14 targets: {met}, expected {want}")
    for x in HEMISPHERE_SEEDS:
        put("sphere_ground", "studio", x, 0.016)  # stable, but every seed over 1.5%
    rows = issue14_targets({"study": study, "hemisphere_pairs": HEMISPHERE_PAIRS})
    if rows[-1][2] != "no":
        faults.append(f"stability row met with every seed at 1.6%: {rows[-1]}")
    for x in HEMISPHERE_SEEDS:
        put("sphere_ground", "studio", x, 0.0045 if x <= 2 else 0.014)  # within 1.5%, but 3.1x and 0.95 points apart
    rows = issue14_targets({"study": study, "hemisphere_pairs": HEMISPHERE_PAIRS})
    if rows[-1][2] != "no":
        faults.append(f"stability row met with seeds 0.45% and 1.4%: {rows[-1]}")

    # The progress line: nothing unless the stream is a terminal; on one, cases, elapsed and what is left.
    class Stream(io.StringIO):
        def __init__(self, tty):
            super().__init__()
            self.tty = tty

        def isatty(self):
            return self.tty

    now = [0.0]
    for tty in (False, True):
        now[0] = 100.0
        stream = Stream(tty)
        p_ = Progress(10, stream, clock=lambda: now[0])
        now[0] = 175.0  # 75 s for the first three cases: 25 s each, 7 to go
        for _ in range(3):
            p_.step()
        if not tty and stream.getvalue():
            faults.append(f"progress written to a stream that is not a terminal: {stream.getvalue()!r}")
        if tty and not stream.getvalue().endswith("3/10 cases, 1:15 elapsed, about 2:55 left"):
            faults.append(f"progress line: {stream.getvalue()!r}")
    if clock_words(3725) != "1:02:05":
        faults.append(f"clock_words(3725) = {clock_words(3725)}")
    for f_ in faults:
        print(f"self-test: {f_}", file=sys.stderr)
    return 1 if faults else 0


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
    global progress
    progress = Progress(sum(1 for j in jobs if result_key(j[0], j[1], j[2], j[3], dict(DEFAULTS, **j[4]), args.error)
                            not in study.results))
    progress.draw()
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futs = [ex.submit(study.measure, s, m, meth, n, **o) for s, m, meth, n, o in jobs]
        for j, f in zip(jobs, futs):
            try:
                f.result()
            except RuntimeError as e:
                failed.append(f"{j}: {str(e).splitlines()[0]}")
    ref_thread.join()
    progress.finish()
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
             "--height", "200", "--specular", spec, "--out", out])
    for t in (0.0, 1.5):
        if args.report_only and os.path.exists(f"{outdir}/fig8_t{t:g}.png"):
            continue
        run([args.bin, "render", "--scene", "assets/scenes/flyover.json", "--lights", "128", "--width", "400",
             "--height", "225", "--time", str(t), "--out", f"{outdir}/fig8_t{t:g}.png"])

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


if __name__ == "__main__":
    main()
