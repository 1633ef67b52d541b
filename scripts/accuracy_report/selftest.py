"""The checks --self-test runs (no build needed)."""
import argparse
import io
import sys

from .config import DEFAULTS, HEMISPHERE_PAIRS, HEMISPHERE_SEEDS
from .progress import clock_words, Progress
from .cache import key_fields, result_key
from .targets import target_rows, TARGETS


# The targets measured over seeds (the made-up results below hold only those cases).
SEED_TARGETS = [t for t in TARGETS if t["kind"] in ("over_seeds", "ground", "ground_stable")]


def self_test():
    """The cache keys and the targets over seeds on made-up results (no build needed); 0 when all hold."""
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
    rows = target_rows({"study": study, "hemisphere_pairs": HEMISPHERE_PAIRS}, SEED_TARGETS)
    met = {r[0].split(":")[1].split(",")[0].strip(): r[2] for r in rows}
    want = {"engine/courtyard": "at seed 1 only", "figure/studio": "yes", "diffuse sphere on a ground": "no",
            "the same": "yes"}
    if met != want:
        faults.append(f"targets over seeds: {met}, expected {want}")
    for x in HEMISPHERE_SEEDS:
        put("sphere_ground", "studio", x, 0.016)  # stable, but every seed over 1.5%
    rows = target_rows({"study": study, "hemisphere_pairs": HEMISPHERE_PAIRS}, SEED_TARGETS)
    if rows[-1][2] != "no":
        faults.append(f"stability row met with every seed at 1.6%: {rows[-1]}")
    for x in HEMISPHERE_SEEDS:
        put("sphere_ground", "studio", x, 0.0045 if x <= 2 else 0.014)  # within 1.5%, but 3.1x and 0.95 points apart
    rows = target_rows({"study": study, "hemisphere_pairs": HEMISPHERE_PAIRS}, SEED_TARGETS)
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
