"""Scenes, maps, methods and the pairs each study covers: the data the runs and the report are made of."""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORLD = "/usr/share/blender/datafiles/studiolights/world"
SCENE_DIR = "docs/accuracy/scenes"

# scene name -> (file, reference width, height, mask scene or None). The sphere scenes are compared over
# the sphere only (a mask rendered from sphere_mask.json / sphere_ground_mask.json), the others over every
# object pixel. A new scene is one row here: --full runs then take it into every study (the specular ones
# only for sphere_n10 and sphere_n100, the diffuse and tile studies only for names not starting "sphere");
# the default run's tables take it where a (scene, map) pair is added to the *_PAIRS lists below.
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
SHADING_NS = NS  # the shading study: cells against ratio, N = 16 ... 256
# hemisphere "auto": the upper hemisphere when the scene has a ground (every scene here has one), else the whole sphere.
# tile_sizes "share": a budget of N x tile^2 texels, each cell's tile sized by its share of the light.
# shading "cells", shadows "hard": the paper's method, which the studies vary (the commands' defaults are
# ratio shading with soft shadows; every run names both, so the cache's images keep their meaning).
DEFAULTS = {"tile": 256, "specular": "blended", "cap": "weighted", "diffuse": "center", "seed": 1, "hemisphere": "auto",
            "tile_sizes": "share", "shading": "cells", "shadows": "hard"}

# What the default run covers. --full: every scene x map in every study.
GRID_PAIRS = [("figure", "city"), ("figure", "studio"), ("sphere_n100", "city"), ("sphere_n100", "studio")]
TABLE_PAIRS = GRID_PAIRS + [("sphere_n10", "city"), ("engine", "courtyard"), ("sphere_n100", "sky")]
SPECULAR_PAIRS = [("sphere_n10", "city"), ("sphere_n100", "city"), ("sphere_n100", "studio")]
DIFFUSE_PAIRS = [("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]
# The shading study: cells against ratio, glossy and diffuse.
SHADING_PAIRS = [("sphere_n10", "city"), ("sphere_n100", "city"), ("sphere_n100", "studio"), ("sphere_n100", "sky"),
                 ("sphere_n1000", "city"), ("sphere_n1000", "studio"), ("sphere_n1000", "sky"),
                 ("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]
TILE_PAIRS = [("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]

# The seed study: the same scene decomposed with other seeds (lloyd and random use one; mediancut and fs do not).
SEED_PAIRS = [("figure", "studio"), ("sphere_n100", "studio"), ("figure", "city")]
SEEDS = [1, 2, 3]

# The hemisphere study: --hemisphere auto (the default; the upper hemisphere on these scenes) against
# --hemisphere full (the whole sphere decomposed, the cells whose centre is below the horizon dropped), lloyd N = 128.
GROUND_PAIRS = [("sphere_ground", "city"), ("sphere_ground", "courtyard"), ("sphere_ground", "studio")]
HEMISPHERE_PAIRS = GROUND_PAIRS + [("figure", "city"), ("figure", "studio"), ("engine", "courtyard")]
HEMISPHERES = ["auto", "full"]
HEMISPHERE_SEEDS = [1, 2, 3, 4]
