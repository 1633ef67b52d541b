"""The result cache: its keys, the reference locks between processes, and whole-or-nothing writes."""
import contextlib
import os
import time

from .config import SCENES
from .progress import log


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
