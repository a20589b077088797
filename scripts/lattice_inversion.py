#!/usr/bin/env python3
"""Whether a box body's lattice turned inside out: runs a scene with the Python module and, for every
body whose shape is a box (a lattice of nodes in rows along x, y and z), counts the rows whose nodes
are no longer in the order they started in (a node at or past its neighbour along the row's axis: a
cell inverted, which a mass-spring lattice does not resist, and a state that is no tissue's).

Usage: scripts/lattice_inversion.py SCENE [--steps N] [--set KEY=JSON ...] [--out FILE.csv]
  SCENE     a scene file or a bundled name; run for --steps steps (default: the scene's time.steps
            plus its settle.max_steps, settling off: a fixed length) with the --set overrides (KEY=JSON,
            as harness run --set)
  --out     the rows as CSV (default: printed)
Rows: body, axis, rows, inverted_rows, deepest_mm (the largest overlap of a node past its neighbour,
mm), first (the first inverted row: its start coordinates in mm and where along it). Bodies of
other shapes are listed with rows empty: no lattice to read the order from.
Needs the harness Python module (build/python on PYTHONPATH).
"""
import argparse
import csv
import json
import sys

import numpy as np

import harness


def inverted_rows(x0, x, axis):
    """(rows, inverted rows, deepest overlap m, first inverted (start, index)) along `axis`."""
    others = [a for a in range(3) if a != axis]
    rows = {}
    for i, p in enumerate(x0):
        rows.setdefault(tuple(round(float(p[a]), 9) for a in others), []).append(i)
    bad, deepest, first = 0, 0.0, None
    for key, idx in sorted(rows.items()):
        if len(idx) < 2:
            continue
        idx = sorted(idx, key=lambda i: x0[i][axis])
        d = np.diff(x[idx, axis])
        if (d <= 0).any():
            bad += 1
            deepest = max(deepest, float(-d.min()))
            if first is None:
                first = ("(%s)" % ", ".join("%.4g" % (1e3 * v) for v in key), int(np.argmax(d <= 0)))
    return sum(len(v) > 1 for v in rows.values()), bad, deepest, first


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--steps", type=int)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    ap.add_argument("--out")
    a = ap.parse_args()
    try:
        scene = harness.Scene.load(a.scene)
        for s in a.sets:
            key, _, value = s.partition("=")
            try:
                value = json.loads(value)
            except ValueError as e:
                raise ValueError("--set %s: the value is not JSON (%s)" % (s, e))
            scene = scene.with_(**{key: value})
        doc = scene.to_dict()
        t = doc.get("time", {})
        steps = a.steps or int(t.get("steps", 0)) + int((t.get("settle") or {}).get("max_steps", 0))
        scene = scene.with_steps(steps)  # as --steps: settling off (sim.step below runs exactly that many)
    except (harness.SceneError, ValueError) as e:
        print("lattice_inversion.py: error: %s" % e, file=sys.stderr)
        sys.exit(2)
    sim = harness.Simulation(scene, threads=1)
    names = [b["name"] for b in doc["bodies"]]
    x0 = {n: np.array(sim.positions(n)) for n in names}
    sim.step(steps)
    out = []
    for b in doc["bodies"]:
        n = b["name"]
        if b["shape"]["type"] != "box":
            out.append({"body": n, "axis": "", "rows": "", "inverted_rows": "", "deepest_mm": "", "first": "not a box"})
            continue
        x = np.array(sim.positions(n))
        for axis in range(3):
            rows, bad, deepest, first = inverted_rows(x0[n], x, axis)
            out.append({"body": n, "axis": "xyz"[axis], "rows": rows, "inverted_rows": bad,
                        "deepest_mm": "%.4g" % (1e3 * deepest),
                        "first": "" if first is None else "row at %s mm, after node %d" % first})
    cols = ["body", "axis", "rows", "inverted_rows", "deepest_mm", "first"]
    f = open(a.out, "w", newline="") if a.out else sys.stdout
    w = csv.DictWriter(f, cols)
    w.writeheader()
    w.writerows(out)
    if a.out:
        f.close()
    print("lattice_inversion.py: %s after %d steps" % (a.scene, steps), file=sys.stderr)


if __name__ == "__main__":
    main()
