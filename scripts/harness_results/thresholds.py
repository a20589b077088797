"""The CI accuracy thresholds (results/thresholds.json; scripts/thresholds.py is the command line):
the bundled scenarios measured as the CI test runs them and compared with their committed references.

Two methods per scenario, each run as the test runs it (settle at most SETTLE more steps, CGAL every
EVERY steps) and compared with the scenario's committed reference (results/references/<scene>/):
  the paper's voxel model  with the default the ablation chose (results/defaults.json); a scenario
                           without one gets no threshold for it, and the file says why;
  the completed model      voxel_exact, both ways, the penalty (k = 500 N/m): COMPLETED below.
The figures are the run's final window (rules.py): position error and gap as window means, depth
and tunnelled nodes as window maxima, recall over the run. Each threshold is the measured value
times a stated margin (MARGIN, at most 1.5), with a floor for the lengths (FLOOR: the scale below
which the reference itself is not trusted) and for tunnelled nodes (1: one node may tunnel at the
measured value 0).
"""

import json
import os
import sys
import tempfile

from . import reader, runner
from .studies.common import SCENES, STUDY_EVERY, force_setting

SETTLE = 4000
EVERY = STUDY_EVERY  # the one sampling rule of runs, sweeps and studies (rules.py)
MARGIN = {"pos_err_max": 1.5, "gap_max": 1.5, "depth_max": 1.5, "tunnelled": 1.5, "recall": 1.1}
FLOOR = 5e-5  # m: the reference's own tolerance
COMPLETED = {"contacts.0.detector": '"voxel_exact"', "contacts.0.eliminator": '"line"',
             "contacts.0.force": '{"stiffness":500}', "contacts.0.two_sided": "true"}
ABOUT = ("CI accuracy thresholds: measured window figures times a margin, against the committed reference "
         "solutions; checked by the ctest 'reference:CI accuracy thresholds hold' with its broken twins. "
         "Made by scripts/thresholds.py.")
WITHOUT = ("the paper's voxel model: the ablation found no stable setting clearly closer to "
           "the reference than no contact force (results/tables/ablation.md): a threshold "
           "could not tell the method from a broken one")


def paper_sets(d):
    """--set overrides of the ablation's default: the paper's voxel model, its eliminator, force, voxel size."""
    force = force_setting(d["force"])
    return {"contacts.0.detector": '"voxel"', "contacts.0.eliminator": '"%s"' % d["eliminator"],
            "contacts.0.force": json.dumps(force) if force == "auto" else force,
            "contacts.0.voxel_size": "%g" % d["voxel_size"], "contacts.0.two_sided": "false"}


def run(a, scene, sets, out):
    """The scene as the CI test runs it (the caller's thread count), compared with its reference."""
    args = ["run", scene, "--out", out, "--quiet", "--compare", os.path.join(a.results, "references", scene),
            "--set", "output.frames_every=0", "--set", 'references.solvers=["cgal"]',
            "--set", "references.every=%d" % EVERY, "--set", "time.settle.max_steps=%d" % SETTLE]
    args += runner.sets_args("%s=%s" % kv for kv in sets.items())
    return runner.harness(a, args, out, check=True, show_stderr=True, cached=False, threads=None)


def measured(s):
    """The window figures the thresholds hold (SI units) and the run's stability verdict."""
    ew = reader.reference_window(s)
    return {"pos_err_max": reader.window_stat(ew, "pos_err_max"), "gap_max": reader.window_stat(ew, "gap_max"),
            "depth_max": reader.window_stat(ew, "depth_max", "max"),
            "tunnelled": reader.window_stat(ew, "tunnelled", "max"), "recall": reader.num(reader.pair_value(s, "recall")),
            "stability_verdict": reader.stability_verdict(s), "git_commit": reader.git_commit(s)}


def thresholds_of(m):
    return {"max_pos_err_max": max(FLOOR, m["pos_err_max"] * MARGIN["pos_err_max"]),
            "max_gap_max": max(FLOOR, m["gap_max"] * MARGIN["gap_max"]),
            "max_depth_max": max(FLOOR, m["depth_max"] * MARGIN["depth_max"]),
            "max_tunnelled": max(1.0, m["tunnelled"] * MARGIN["tunnelled"]),
            "min_recall": m["recall"] / MARGIN["recall"]}


def methods_of(scene, defaults, doc):
    """(kind, label, --set overrides) of the methods a scene is measured with: the paper's voxel model
    where the ablation chose a default for it (else said in doc["without"]), and the completed model."""
    methods = [("completed", "voxel_exact, both ways, k = 500 N/m", COMPLETED)]
    if defaults.get(scene):
        methods.insert(0, ("paper", "the paper's voxel model, the ablation's default", paper_sets(defaults[scene])))
    else:
        doc["without"][scene] = WITHOUT
        print("thresholds: %s has no voxel default; no threshold for the paper's model (said in the file)" % scene,
              file=sys.stderr)
    return methods


def measure(a, defaults):
    """thresholds.json's document: every scene's methods run (in a temporary folder) and measured."""
    doc = {"about": ABOUT, "every": EVERY, "settle_max_steps": SETTLE, "margins": MARGIN, "floor": FLOOR,
           "checks": [], "without": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for scene in SCENES:
            for kind, label, sets in methods_of(scene, defaults, doc):
                s = run(a, scene, sets, os.path.join(tmp, "%s_%s" % (scene, kind)))
                m = measured(s)
                if m["stability_verdict"] not in ("settled", "steady"):
                    print("thresholds: %s, %s: verdict %s; thresholds kept from its figures all the same" % (
                        scene, label, m["stability_verdict"]), file=sys.stderr)
                doc["checks"].append(dict(scene=scene, method=kind, label=label, sets=sets, measured=m,
                                          **thresholds_of(m)))
    return doc


def write(a):
    """Measures (measure) with the ablation's defaults of a.results (defaults.json: it must be there)
    and writes a.results/thresholds.json."""
    with open(os.path.join(a.results, "defaults.json")) as f:  # must be there: the ablation's defaults
        defaults = json.load(f)
    doc = measure(a, defaults)
    out = os.path.join(a.results, "thresholds.json")
    with open(out, "w") as f:
        json.dump(doc, f, indent=2, sort_keys=True)
        f.write("\n")
    print("thresholds: written to %s" % out, file=sys.stderr)
