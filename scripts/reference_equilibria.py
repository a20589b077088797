#!/usr/bin/env python3
"""Whether a reference's jump between two levels is a switch between equilibria: results/reference_equilibria.csv.

A reference (`harness reference`) halves dt and doubles the penalty from level to level; where two
levels' settled surfaces are much farther apart than the levels before and after (an order of
convergence outside reader.SANE_ORDER), the loop is not in its asymptotic range. Two causes give
that: the discretisation changes the answer (one equilibrium per level, moving), or the problem has
two equilibria and the levels settle into different ones from rest. This tells them apart: level A
and level B of the reference are stepped from rest to their settled states (the reference's own
step counts); then A is started again from B's settled state (after its forcing, velocities zero)
and B from A's, each stepped until its force residual is below the reference's tolerance. Where
each stays where it was started (closer to the state it started from than to its own state from
rest by a factor FACTOR or more), both states are equilibria of both levels: "two equilibria", and
the levels' jump is the distance between them, not a discretisation error. Otherwise "one
equilibrium per level".

Usage: reference_equilibria.py [REFERENCE ...] [--results results] [--harness build/bin/harness]
  REFERENCE: a folder name under results/references/ (default: every reference whose last order is
  outside reader.SANE_ORDER); the two levels are those of its largest change.
Needs the Python module (PYTHONPATH=build/python, the README's build). About 4 min for the
implant's one-sided reference on this machine.
Exit status: 0 done; 2 bad input.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

from harness_results import reader, rules, writers

FACTOR = 10.0
CHUNK = 5000
MAX_CHUNKS = 40
COLUMNS = ["reference", "level_a", "level_b", "dt_a", "dt_b", "stiffness_a", "stiffness_b", "apart_mm",
           "a_from_b_to_b_mm", "a_from_b_to_a_mm", "a_from_b_residual", "b_from_a_to_a_mm", "b_from_a_to_b_mm",
           "b_from_a_residual", "verdict"]


def level_scene(harness, ref, level, tmp):
    """The scene of one level of reference summary `ref` (its resolved scene's contact and settle, the
    level's dt and stiffness, step counts scaled by the harness: --dt), with an open step count."""
    base = ref["resolved_scene"]
    c = base["contacts"][0]
    scene = reader.scene_file(ref) if os.path.isfile(str(reader.scene_file(ref) or "")) else reader.scene(ref)
    out = os.path.join(tmp, "level%d" % level["level"])
    cmd = [harness, "run", scene, "--dt", repr(level["dt"]), "--steps", "1", "--quiet", "--out", out,
           "--set", "contacts.0.detector=" + json.dumps(c["detector"]),
           "--set", "contacts.0.eliminator=" + json.dumps(c["eliminator"]),
           "--set", "contacts.0.force=" + json.dumps({"stiffness": level["stiffness"]}),
           "--set", "contacts.0.two_sided=" + json.dumps(bool(c.get("two_sided"))),
           "--set", "references.solvers=[]", "--set", "time.guard=" + json.dumps(base["time"].get("guard", "refuse"))]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("level %d's scene: %s" % (level["level"], p.stderr.strip()))
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)["resolved_scene"]
    s["time"]["steps"] = 10 ** 8
    s["time"].pop("settle", None)
    return s


def positions(sim, bodies):
    return {b: np.array(sim.positions(b)) for b in bodies}


def apart_mm(a, b):
    """The largest distance of a node between two states (every body), mm."""
    return 1e3 * max(float(np.max(np.linalg.norm(a[k] - b[k], axis=1))) for k in a)


def settle_from(harness_mod, scene, start, tolerance):
    """A simulation of `scene` stepped through its forcing, then put in `start` at rest and stepped
    until its residual is below `tolerance` (MAX_CHUNKS chunks at most): (state, residual)."""
    sim = harness_mod.Simulation(scene)
    n = rules.forcing_end_of(scene) or 0
    if n:
        sim.step(n)
    for b, x in start.items():
        sim.set_positions(b, x)
        sim.set_velocities(b, np.zeros_like(x))
    res = float("inf")
    for _ in range(MAX_CHUNKS):
        sim.step(CHUNK)
        res = sim.energy()["residual"]
        if res < tolerance:
            break
    return positions(sim, start), res


def study(harness, harness_mod, root, name):
    path = os.path.join(root, "references", name)
    ref = reader.load_summary(path)
    levels = reader.reference_levels(ref)[0]
    changes = [(reader.num(lv.get("change_max")), i) for i, lv in enumerate(levels) if reader.present(lv.get("change_max"))]
    if not changes:
        raise RuntimeError("%s: fewer than two levels" % name)
    _c, i = max(changes)
    la, lb = levels[i - 1], levels[i]
    tol = reader.num((ref["resolved_scene"]["time"].get("settle") or {}).get("tolerance"), 1e-5)
    bodies = [b["name"] for b in ref["resolved_scene"]["bodies"]]
    with tempfile.TemporaryDirectory() as tmp:
        sa, sb = level_scene(harness, ref, la, tmp), level_scene(harness, ref, lb, tmp)
    rest = {}
    for key, sc, lv in (("a", sa, la), ("b", sb, lb)):
        sim = harness_mod.Simulation(sc)
        sim.step(int(lv["steps_run"]))
        rest[key] = positions(sim, bodies)
        print("reference_equilibria: %s level %d from rest: residual %.3g" % (name, lv["level"], sim.energy()["residual"]),
              flush=True)
    a_b, ra = settle_from(harness_mod, sa, rest["b"], tol)
    b_a, rb = settle_from(harness_mod, sb, rest["a"], tol)
    apart = apart_mm(rest["a"], rest["b"])
    row = {"reference": name, "level_a": la["level"], "level_b": lb["level"], "dt_a": la["dt"], "dt_b": lb["dt"],
           "stiffness_a": la["stiffness"], "stiffness_b": lb["stiffness"], "apart_mm": apart,
           "a_from_b_to_b_mm": apart_mm(a_b, rest["b"]), "a_from_b_to_a_mm": apart_mm(a_b, rest["a"]),
           "a_from_b_residual": ra, "b_from_a_to_a_mm": apart_mm(b_a, rest["a"]),
           "b_from_a_to_b_mm": apart_mm(b_a, rest["b"]), "b_from_a_residual": rb}
    two = (row["a_from_b_to_b_mm"] * FACTOR <= row["a_from_b_to_a_mm"] and
           row["b_from_a_to_a_mm"] * FACTOR <= row["b_from_a_to_b_mm"] and ra < tol and rb < tol)
    row["verdict"] = "two equilibria" if two else "one equilibrium per level"
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("references", nargs="*")
    ap.add_argument("--results", default="results")
    ap.add_argument("--harness", default="build/bin/harness")
    a = ap.parse_args()
    refdir = os.path.join(a.results, "references")
    if not os.path.isdir(refdir):
        print("reference_equilibria: %s: no references folder" % refdir, file=sys.stderr)
        sys.exit(2)
    try:
        import harness as harness_mod
    except ImportError:
        print("reference_equilibria: the Python module is missing (PYTHONPATH=build/python after scripts/build.sh)",
              file=sys.stderr)
        sys.exit(2)
    names = a.references
    if not names:
        for n in sorted(os.listdir(refdir)):
            s = reader.load_summary(os.path.join(refdir, n)) if reader.has_summary(os.path.join(refdir, n)) else None
            lv = reader.reference_levels(s)[0] if s and s.get("reference") else []
            order = reader.num(lv[-1].get("order")) if lv else float("nan")
            if reader.present(order) and not math.isnan(order) and not (
                    reader.SANE_ORDER[0] <= order <= reader.SANE_ORDER[1]):
                names.append(n)
    for n in names:
        if not reader.has_summary(os.path.join(refdir, n)):
            print("reference_equilibria: %s: no reference there" % os.path.join(refdir, n), file=sys.stderr)
            sys.exit(2)
    rows = [study(a.harness, harness_mod, a.results, n) for n in names]
    for r in rows:
        print("reference_equilibria: %s levels %d/%d %.4g mm apart: %s (a from b's state %.4g mm from b; b from a's "
              "%.4g mm from a)" % (r["reference"], r["level_a"], r["level_b"], r["apart_mm"], r["verdict"],
                                   r["a_from_b_to_b_mm"], r["b_from_a_to_a_mm"]))
    path = os.path.join(a.results, "reference_equilibria.csv")
    writers.write_csv(path, rows, COLUMNS)
    print("reference_equilibria: wrote %s" % path)


if __name__ == "__main__":
    main()
