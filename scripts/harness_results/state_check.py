"""The GPU's final states against the CPU's: results/device/state_check.csv (scripts/device_state_check.py
is the command line, whose docstring says how each row is made).

Rows: every device run of RESULTS_DIR/device/runs/; one with a `cpu_check` in its summary.json (made
on the GPU machine by `harness run --device cuda --check-cpu`) as recorded, one without it (a full
run, `*_voxel_exact_full`) checked here by running the CPU (cpu_run; `--device cpu` where the
hashes differ, and the largest node distance to the GPU's state.csv.gz).
"""

import csv
import gzip
import math
import os
import subprocess
import sys
import tempfile

from . import reader

COLUMNS = ["scene", "config", "steps", "contacts_last", "gpu_state_hash", "cpu_state_hash", "bit_identical",
           "max_node_distance_m", "how"]


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
    return reader.load_summary(out)


def checked_here(harness, folder, s):
    """The columns of a device run without a cpu_check: the CPU's run of as many steps, its state
    hash against the GPU's and, where they differ, the largest node distance of the device's kernel
    bodies on the CPU (--device cpu) to the GPU's state.csv.gz."""
    scene, steps = reader.scene(s), reader.steps_run(s)
    with tempfile.TemporaryDirectory() as tmp:
        cpu = cpu_run(harness, scene, steps, os.path.join(tmp, "cpu"))
        same = reader.state_hash(cpu) == reader.state_hash(s)
        far = 0.0
        if not same:
            cpu_run(harness, scene, steps, os.path.join(tmp, "dev"), device="cpu")
            a = positions(os.path.join(folder, "state.csv.gz"))
            b = positions(os.path.join(tmp, "dev", "state.csv"))
            far = max(math.dist(p, q) for p, q in zip(a, b))
    return dict(cpu_state_hash=reader.state_hash(cpu), bit_identical=str(same).lower(),
                max_node_distance_m="%.3g" % far,
                how="scripts/device_state_check.py: the CPU's run and state.csv against the GPU's state.csv.gz")


def state_row(harness, folder, name):
    """state_check.csv's row of the device run in `folder` (named `name`)."""
    s = reader.load_summary(folder)
    scene = reader.scene(s)
    row = {"scene": scene, "config": name[len(scene) + 1:], "steps": reader.steps_run(s),
           "contacts_last": reader.contacts_last(s), "gpu_state_hash": reader.state_hash(s)}
    c = reader.cpu_check(s)
    if c:
        row.update(cpu_state_hash=c["cpu_state_hash"], bit_identical=str(c["bit_identical"]).lower(),
                   max_node_distance_m="%.3g" % c["max_node_distance_m"],
                   how="harness run --device cuda --check-cpu (on the GPU machine)")
    else:
        row.update(checked_here(harness, folder, s))
    return row


def write(results, harness):
    """results/device/state_check.csv from the device runs of results/device/runs/ (harness: the CPU's
    harness, run for the runs without a cpu_check)."""
    runs = os.path.join(results, "device", "runs")
    rows = []
    for name in sorted(os.listdir(runs)):
        row = state_row(harness, os.path.join(runs, name), name)
        rows.append(row)
        print("device_state_check: %s %s: %s steps, identical %s, %s m" % (
            row["scene"], row["config"], row["steps"], row["bit_identical"], row["max_node_distance_m"]),
            file=sys.stderr)
    path = os.path.join(results, "device", "state_check.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, COLUMNS, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    print("device_state_check: wrote %s" % path, file=sys.stderr)
