#!/usr/bin/env python3
"""Measures a finished run against a second reference without making it again in the results:
each run folder is run again from the scene its summary.json resolved, with --compare (the reference
it was measured against) and --compare-also (the second), into a temporary folder; where the run
ends in the same state (state_hash) and its first reference's figures are the same, the second
reference's figures (each pair's error_vs_reference_also) are written into the folder's
summary.json, with `compare_also` saying how they were obtained. The folder's steps.csv, frames and
timings are left as they are (the rerun's timings are not the run's). A run that does not end in
the same state is left untouched and named (exit 1).

The report's runs (results/runs/, scripts/reproduce.sh) are one-sided (the paper's model):
`runs_compare_also.py results/runs --reference-suffix _one_sided` measures each against its
scene's one-sided reference (results/references/<scene>_one_sided), the reference of its kind.

Usage: runs_compare_also.py RUNS_DIR [--harness build/bin/harness] [--references results/references]
                            [--reference-suffix _one_sided] [-j 2] [--only FOLDER ...]
Exit status: 0 done, 1 a run did not reproduce, 2 bad input.
"""

import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

from harness_results import writers

# The first reference's figures that must be the same in the rerun (the window's and the end's).
SAME = ("pos_err_max", "pos_err_rms", "gap_max", "depth_max", "depth_peak")


def rerun(harness, folder, references, suffix):
    """(folder, message, the summary to write or None)."""
    path = os.path.join(folder, "summary.json")
    with open(path) as f:
        s = json.load(f)
    scene = s.get("scene")
    first = os.path.join(references, scene)
    second = os.path.join(references, scene + suffix)
    if not os.path.isfile(os.path.join(second, "summary.json")):
        return folder, "no reference %s: left as it is" % second, None
    with tempfile.TemporaryDirectory() as tmp:
        scene_file = os.path.join(tmp, "scene.json")
        with open(scene_file, "w") as f:
            json.dump(s["resolved_scene"], f)
        out = os.path.join(tmp, "run")
        cmd = [harness, "run", scene_file, "--out", out, "--quiet", "--compare", first, "--compare-also", second]
        p = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, HARNESS_THREADS="1"))
        if p.returncode != 0:
            return folder, "rerun exited %d: %s" % (p.returncode, p.stderr.strip().splitlines()[-1:]), None
        with open(os.path.join(out, "summary.json")) as f:
            new = json.load(f)
    if new.get("state_hash") != s.get("state_hash"):
        return folder, "rerun ends in another state (%s, committed %s): not written" % (
            new.get("state_hash"), s.get("state_hash")), None
    for old_p, new_p in zip(s.get("pairs", []), new.get("pairs", [])):
        a, b = old_p.get("error_vs_reference") or {}, new_p.get("error_vs_reference") or {}
        for k in SAME:
            if a.get(k) != b.get(k):
                return folder, "rerun's %s against the first reference differs (%s, committed %s): not written" % (
                    k, b.get(k), a.get(k)), None
        if (a.get("window") or {}) != (b.get("window") or {}):
            return folder, "rerun's window figures against the first reference differ: not written", None
        old_p["error_vs_reference_also"] = new_p.get("error_vs_reference_also")
    s["compare_also"] = {"reference": second, "how": "run again from resolved_scene with --compare-also "
                         "(scripts/runs_compare_also.py); the same state_hash and the same figures against "
                         "the first reference; steps.csv, frames and timings are the first run's"}
    return folder, "ok (state %s)" % s["state_hash"][:12], s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs")
    ap.add_argument("--harness", default="build/bin/harness")
    ap.add_argument("--references", default="results/references")
    ap.add_argument("--reference-suffix", default="_one_sided")
    ap.add_argument("-j", type=int, default=2)
    ap.add_argument("--only", nargs="*")
    a = ap.parse_args()
    if not os.path.isdir(a.runs):
        print("runs_compare_also: %s: not a folder" % a.runs, file=sys.stderr)
        sys.exit(2)
    if not os.access(a.harness, os.X_OK):
        print("runs_compare_also: %s: no harness there (scripts/build.sh)" % a.harness, file=sys.stderr)
        sys.exit(2)
    folders = sorted(os.path.join(a.runs, d) for d in os.listdir(a.runs)
                     if os.path.isfile(os.path.join(a.runs, d, "summary.json")) and (not a.only or d in a.only))
    bad = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.j)) as ex:
        for folder, msg, s in ex.map(lambda d: rerun(a.harness, d, a.references, a.reference_suffix), folders):
            print("runs_compare_also: %s: %s" % (folder, msg))
            if s is not None:
                writers.write_text(os.path.join(folder, "summary.json"), json.dumps(s, indent=2, sort_keys=True) + "\n")
            elif not msg.startswith("no reference"):
                bad += 1
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
