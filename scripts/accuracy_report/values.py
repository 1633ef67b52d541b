"""Numbers the report and the targets read from a run."""
from .config import HEMISPHERE_SEEDS


def pct(x):
    return f"{100 * x:.2f}%"


def rr(ctx, scene, map_, m="lloyd", n=128, **o):
    r = ctx["study"].results_for(scene, map_, m, n, **o)
    return r["rel_rmse"] if r else None


def cell(x):
    return "–" if x is None else pct(x)


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
