"""study.py detection: claim (d) as the paper states it, detection alone. `harness detection` runs
each scene as it is written (its own contact response) and keeps STATES states over its steps, and
takes the generated bench scenes' initial states at SIZES nodes per body; on those same states it
times every detector's one-sided detection (one thread, the detectors taking turns round by round)
and scores its two-sided reports node by node against CGAL's exact sets (recall and precision,
guest and host) -> detection.csv, tables/detection.md (the verdict is in claims.md).
With --scene FILE the user's scene alone, no bench sizes.
"""

import os
import subprocess
import sys

from .. import reader, writers
from .common import scene_arg, scenes, table_path

STATES = 20
SIZES = [1000, 10000, 100000, 1000000]
QUICK = {"states": 3, "sizes": [1000], "min_time": 0.05}


def run(a):
    user = getattr(a, "user", None)
    out = os.path.join(a.results, "detection.csv")
    args = [a.harness, "detection"] + [scene_arg(a, s) for s in scenes(a)] + ["--out", out]
    if a.quick:
        args += ["--states", str(QUICK["states"]), "--min-time", str(QUICK["min_time"])]
        sizes = QUICK["sizes"]
    else:
        args += ["--states", str(STATES)]
        sizes = SIZES
    if not user:
        args += ["--sizes", ",".join(str(n) for n in sizes)]
    for s in getattr(a, "extra_sets", []):  # --quick: short runs
        args += ["--set", s]
    print("study: " + " ".join(args), file=sys.stderr)
    subprocess.run(args, check=True)
    plots(a)


TEXT = ["source", "kind", "pair", "detector", "setting", "device", "machine"]
COLUMNS = ["source", "detector", "setting", "voxel_mm", "states", "detect_us", "detect_min_us", "detect_max_us",
           "detect_warm_us",
           "true_pen_guest", "recall", "precision", "true_pen_host", "recall_host", "precision_host", "beyond_band"]


def read(a):
    return reader.read_csv(os.path.join(a.results, "detection.csv"), text=TEXT, missing=[])


def plots(a):
    """tables/detection.md from detection.csv (nothing is run)."""
    rows = read(a)
    if not rows:
        return
    md = ["# Detection alone, every detector on the same states\n\n",
          "Made by `scripts/study.py detection` (`harness detection`; experiments/detection.hpp says how). "
          "Per source: the states of the scene's own run (%s states over its steps) or a generated bench "
          "scene's initial state (nodes per body in its name). Time: one-sided detection, one thread, µs per "
          "state (median over rounds; min and max over rounds), the first call on a state after the other "
          "detectors (cold) and the same call repeated at once (warm). Quality: two-sided reports against CGAL's "
          "exact sets summed over the states (nodes strictly inside the other body, interior nodes too); "
          "recall and precision empty where nothing penetrates or nothing was reported. Machine: %s. "
          "The verdict is in claims.md.\n\n" % (
              ", ".join(sorted({"%d" % r["states"] for r in rows if r["kind"] == "scene"})) or "-",
              rows[0].get("machine", "-")),
          writers.md_table(rows, COLUMNS, ["source", "detector", "setting", "voxel (mm)", "states", "detect (µs)", "min",
                                           "max", "warm (µs)", "pen. guest", "recall", "precision", "pen. host", "recall host",
                                           "precision host", "beyond band"])]
    with open(table_path(a, "detection.md"), "w") as f:
        f.write("".join(md))
