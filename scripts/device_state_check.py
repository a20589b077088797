#!/usr/bin/env python3
"""The GPU's final states against the CPU's: results/device/state_check.csv.

Usage: device_state_check.py [RESULTS_DIR] [HARNESS]   (defaults: results, build/bin/harness)

Rows: every device run of RESULTS_DIR/device/runs/ with a `cpu_check` in its summary.json (made
on the GPU machine by `harness run --device cuda --check-cpu`), as recorded; and every full run
(`*_voxel_exact_full`, whose summary has no cpu_check: made before device_check.sh passed
--check-cpu to them) checked here: the CPU's `harness run SCENE --steps N --set
contacts.0.detector='"voxel_exact"' --set references.solvers='[]'` gives its state hash; where the
hashes differ, `harness run ... --device cpu` (the device's kernel bodies on the CPU, bit-identical
to the CPU's step: ctest gpu_kernels_*) gives its state.csv, and the largest node distance to the
GPU's state.csv.gz is computed. Runs the CPU for a few minutes; run with /usr/bin/python3 or
$PYTHON.
"""

import csv
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile


def positions(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return [tuple(float(v) for v in r[1:4]) for r in csv.reader(f) if r and r[0] != "node"]


def cpu_run(harness, scene, steps, out, device=None):
    cmd = [harness, "run", scene, "--steps", str(steps), "--quiet", "--out", out,
           "--set", 'contacts.0.detector="voxel_exact"', "--set", "references.solvers=[]"]
    if device:
        cmd += ["--device", device]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def main(argv):
    results = argv[1] if len(argv) > 1 else "results"
    harness = argv[2] if len(argv) > 2 else os.path.join("build", "bin", "harness")
    runs = os.path.join(results, "device", "runs")
    rows = []
    for name in sorted(os.listdir(runs)):
        with open(os.path.join(runs, name, "summary.json")) as f:
            s = json.load(f)
        scene = s["scene"]
        contacts = (s.get("pairs") or [{}])[0].get("contacts_last", "")
        row = {"scene": scene, "config": name[len(scene) + 1:], "steps": s["steps_run"], "contacts_last": contacts,
               "gpu_state_hash": s["state_hash"]}
        c = s.get("cpu_check")
        if c:
            row.update(cpu_state_hash=c["cpu_state_hash"], bit_identical=str(c["bit_identical"]).lower(),
                       max_node_distance_m="%.3g" % c["max_node_distance_m"],
                       how="harness run --device cuda --check-cpu (on the GPU machine)")
        else:
            with tempfile.TemporaryDirectory() as tmp:
                cpu = cpu_run(harness, scene, s["steps_run"], os.path.join(tmp, "cpu"))
                same = cpu["state_hash"] == s["state_hash"]
                far = 0.0
                if not same:
                    cpu_run(harness, scene, s["steps_run"], os.path.join(tmp, "dev"), device="cpu")
                    a = positions(os.path.join(runs, name, "state.csv.gz"))
                    b = positions(os.path.join(tmp, "dev", "state.csv"))
                    far = max(math.dist(p, q) for p, q in zip(a, b))
            row.update(cpu_state_hash=cpu["state_hash"], bit_identical=str(same).lower(),
                       max_node_distance_m="%.3g" % far,
                       how="scripts/device_state_check.py: the CPU's run and state.csv against the GPU's state.csv.gz")
        rows.append(row)
        print("device_state_check: %s %s: %s steps, identical %s, %s m" % (
            scene, row["config"], row["steps"], row["bit_identical"], row["max_node_distance_m"]), file=sys.stderr)
    cols = ["scene", "config", "steps", "contacts_last", "gpu_state_hash", "cpu_state_hash", "bit_identical",
            "max_node_distance_m", "how"]
    path = os.path.join(results, "device", "state_check.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, cols, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    print("device_state_check: wrote %s" % path, file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv)
