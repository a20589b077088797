#!/usr/bin/env python3
"""Measure the bundled scenarios and write results/thresholds.json: the CI accuracy thresholds.

Per scenario, the paper's voxel model with the default the ablation chose (results/defaults.json)
is run as the test runs it (settle at most SETTLE more steps, CGAL every EVERY steps) and compared
with the scenario's committed reference (results/references/<scene>/). Each threshold is the
measured value times a stated margin (at most 1.5):
  max_pos_err_max  largest distance of a surface vertex from the reference      x 1.5
  max_gap_max      largest gap where the reference has contact                  x 1.5
  max_depth_max    deepest penetration                                          x 1.5
  min_recall       detected / truly penetrating guest nodes (1 when none)       / 1.1
(with a floor of FLOOR for the errors, the scale below which the reference itself is not
trusted). Run deliberately, after a change that is meant to move accuracy (it is NOT part of
reproduce.sh: thresholds must not follow the code automatically).
Usage: scripts/thresholds.py [--harness build/bin/harness] [--results results]
"""
import argparse
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness_results import reader, runner  # noqa: E402
from harness_results.studies.common import SCENES, force_setting  # noqa: E402

SETTLE = 4000
EVERY = 50
MARGIN = {"pos_err_max": 1.5, "gap_max": 1.5, "depth_max": 1.5, "recall": 1.1}
FLOOR = 5e-5  # m: the reference's own tolerance


def method_sets(d):
    """--set overrides of the chosen default: voxel model, its eliminator, force, voxel size."""
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--harness", default="build/bin/harness")
    ap.add_argument("--results", default="results")
    a = ap.parse_args()
    with open(os.path.join(a.results, "defaults.json")) as f:  # must be there: the ablation's defaults
        defaults = json.load(f)
    doc = {"about": "CI accuracy thresholds: measured value times margin, against the committed reference "
                    "solutions; checked by the ctest 'reference:CI accuracy thresholds hold' with its broken "
                    "twins. Made by scripts/thresholds.py.",
           "every": EVERY, "settle_max_steps": SETTLE, "margins": MARGIN, "floor": FLOOR, "scenes": {},
           "without": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for scene in SCENES:
            if not defaults.get(scene):
                doc["without"][scene] = ("the ablation found no stable setting of the voxel model clearly closer to "
                                         "the reference than no contact force (results/tables/ablation.md): a "
                                         "threshold could not tell the method from a broken one")
                print("thresholds: %s has no voxel default; no threshold (said in the file)" % scene, file=sys.stderr)
                continue
            sets = method_sets(defaults[scene])
            s = run(a, scene, sets, os.path.join(tmp, scene))
            p = reader.pair(s)
            e = reader.final_reference_errors(s)
            doc["scenes"][scene] = {
                "method": sets,
                "measured": {"pos_err_max": e["pos_err_max"], "gap_max": e["gap_max"], "depth_max": e["depth_max"],
                             "recall": p["recall"], "git_commit": reader.git_commit(s)},
                "max_pos_err_max": max(FLOOR, e["pos_err_max"] * MARGIN["pos_err_max"]),
                "max_gap_max": max(FLOOR, e["gap_max"] * MARGIN["gap_max"]),
                "max_depth_max": max(FLOOR, e["depth_max"] * MARGIN["depth_max"]),
                "min_recall": p["recall"] / MARGIN["recall"],
            }
    out = os.path.join(a.results, "thresholds.json")
    with open(out, "w") as f:
        json.dump(doc, f, indent=2, sort_keys=True)
        f.write("\n")
    print("thresholds: written to %s" % out, file=sys.stderr)


if __name__ == "__main__":
    main()
