"""The studies of the report, one module each, all judged by the error against a converged reference
solution (rules.py states the definitions). Each module has `run(a)` (runs its configurations
through runner.py, writes its CSV, tables and figures) and, when it draws figures, `plots(a)` (the
figures again from its CSV, nothing run: study.py --plots-only). `a` is study.py's parsed command line.

To add a study: a module here with `run(a)` (and `plots(a)`), its name in ORDER, its outputs in
results/README.md.
"""

import importlib
import os
import sys

from .. import counts, reader, runner
from . import common

# The order of `study.py all`.
ORDER = ["references", "accuracy", "ablation", "convergence", "refinement", "realtime", "realtime_grid", "swap", "region", "orient",
         "bullet", "detection", "restriction", "regime", "ensemble"]
# The studies that run on a user's scene (--scene FILE|NAME --out DIR): the same code as the
# bundled ones, the scene's own eliminator, footing voxels from its host's node spacing, its
# reference (--reference DIR, or made into DIR/references/<name>).
USER_STUDIES = ["accuracy", "ablation", "convergence", "refinement", "realtime", "swap", "detection", "restriction", "regime"]


def module(name):
    """The module of study `name`."""
    return importlib.import_module("." + name, __name__)


def use_user_scene(a):
    """study.py --scene: the studies run on a.scene with every output in a.out (default
    studies/<name>); its reference (a.reference, else made into a.out/references/<name> unless
    --plots-only)."""
    user = common.set_user_scene(a, a.scene, a.out or os.path.join("studies", os.path.basename(a.scene).split(".")[0]),
                                 a.reference, getattr(a, "voxel", None))
    if not a.plots_only and not reader.has_summary(user["reference"]):
        print("study: making the reference of %s into %s" % (a.scene, user["reference"]), file=sys.stderr)
        runner.reference(a, user["path"], user["reference"])


def run_all(a):
    """The studies a.what names ("all": ORDER) in turn: each run (study.run), or with --plots-only
    its tables and figures again from its CSV (study.plots, where it has one); then, unless
    --plots-only or on a user's scene, tables/counts.tex written again."""
    a.extra_sets = ["time.steps=300"] if a.quick else []
    if a.quick:
        a.repeats = 1
    for d in ["figures", "tables"]:
        os.makedirs(os.path.join(a.results, d), exist_ok=True)
    for w in (ORDER if "all" in a.what else a.what):
        study = module(w)
        if a.plots_only:
            if hasattr(study, "plots"):
                print("study: %s figures from the CSV" % w, file=sys.stderr)
                study.plots(a)
            continue
        print("study:", w, file=sys.stderr)
        study.run(a)
    if not a.plots_only and not a.scene:
        counts.write(a.results)  # the report's counts follow the results
