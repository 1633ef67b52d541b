"""Running envshadow: references, renders and comparisons (Study), frame-time benches, decompositions."""
import contextlib
import csv
import json
import os
import re
import subprocess
import threading
import time

from .config import DECOMPOSE_METHODS, DEFAULTS, MAPS, ROOT, SCENES
from .progress import lock, log, step
from .cache import atomic_open, result_key, wait_for_lock


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
        return f"{self.cache}/ref/{scene}__{map_}__{w}x{h}__e{self.a.error}__point.exr"

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
                         str(h), "--error", str(self.a.error), "--pixel-filter", "point", "--exr", out + ".tmp.exr"])
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
             "--tile-sizes", o["tile_sizes"], "--shading", o["shading"], "--shadows", o["shadows"],
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
        step()
        return r


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
