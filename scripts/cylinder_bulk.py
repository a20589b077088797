#!/usr/bin/env python3
"""The cylinder's references with a layer that resists inversion (docs/findings.md, "Why the
cylinder's two-sided reference does not converge"): results/cylinder_bulk/ (made by its run.sh:
effect bulk, bulk modulus 1e4 Pa; the layer's surface quads split along aligned or alternating
diagonals; alternating with a cylinder of 48 segments; both kinds of reference) beside the scene's own references (results/references/,
results/references.csv) -> results/cylinder_bulk.csv.

Rows, per layer (variant: "springs" the scene as it is, then VARIANTS), kind
(two-sided, one-sided) and level:
  change_mm     the reference's change from the level before (its summary; for "springs" references.csv)
  twist_mm      half the difference of the sideways offsets y at x = -25 and +25 mm of the layer's top row
                under the cylinder's axis (start y = 0, z = 20 mm): the part of its shape that the half
                turn about z keeps and the mirrors do not (0 for a mirror-symmetric state)
  top_z_mm      that row's height at x = 0
  kinds_gap_mm  (last level only) the largest distance between the two kinds' settled surfaces
Then rows of kind "inversion": the layer's inverted vertical rows at level 0, both ways and one way,
of the scene and of each variant (inversion.csv, inversion48.csv; results/lattice_inversion.csv for
"springs").
Usage: scripts/cylinder_bulk.py [RESULTS]   (default results)
"""
import csv
import json
import os
import sys

import numpy as np

from harness_results import reader


def load(path):
    bodies = {}
    with reader.open_text(path) as f:  # plain or gzipped (results/README.md)
        for r in csv.DictReader(f):
            bodies.setdefault(r["body"], []).append([float(r[k]) for k in ("x", "y", "z", "x0", "y0", "z0")])
    return {k: np.array(v) for k, v in bodies.items()}


def top_row(state):
    """(twist mm, z at x = 0 mm) of the layer's top row under the axis."""
    b = state["layer"]
    row = b[(np.abs(b[:, 4]) < 1e-9) & (np.abs(b[:, 5] - 0.02) < 1e-9)]
    at = {round(x * 1e3, 6): (y, z) for x, y, z in zip(row[:, 3], row[:, 1], row[:, 2])}
    return 0.5 * (at[-25.0][0] - at[25.0][0]) * 1e3, at[0.0][1] * 1e3


def gap(a, b):
    return max(np.linalg.norm(a[k][:, :3] - b[k][:, :3], axis=1).max() for k in a) * 1e3


# (variant, folder stem under results/cylinder_bulk/)
VARIANTS = (("bulk aligned", "aligned"), ("bulk alternating", "alternating"),
            ("bulk alternating, cylinder 48 segments", "alternating48"))


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    d = os.path.join(root, "cylinder_bulk")
    rows = []
    # The scene as it is: its references' levels (references.csv) and final surfaces.
    recorded = {}
    with open(os.path.join(root, "references.csv")) as f:
        for r in csv.DictReader(f):
            recorded.setdefault(r["reference"], []).append(r)
    final = {}
    for kind, name in (("two-sided", "cylinder_press"), ("one-sided", "cylinder_press_one_sided")):
        final[kind] = load(os.path.join(root, "references", name, "surfaces.csv"))
        levels = recorded[name]
        for i, r in enumerate(levels):
            last = i == len(levels) - 1
            tw, z = top_row(final[kind]) if last else (None, None)
            rows.append({"variant": "springs", "kind": kind, "level": r["level"], "dt": r["dt"], "k_c": r["stiffness"],
                         "change_mm": r["change_mm"], "twist_mm": tw, "top_z_mm": z,
                         "converged": r["converged"] if last else ""})
    rows[-1]["kinds_gap_mm"] = gap(final["two-sided"], final["one-sided"])
    for variant, stem in VARIANTS:
        final = {}
        for kind, sfx in (("two-sided", "two"), ("one-sided", "one")):
            base = os.path.join(d, "%s_%s" % (stem, sfx))
            final[kind] = load(os.path.join(base, "surfaces.csv"))
            summary = json.load(open(os.path.join(base, "summary.json")))["reference"]
            for lv in summary["levels"]:
                tw, z = top_row(load(os.path.join(base, "levels", str(lv["level"]), "surfaces.csv")))
                ch = lv["change_max"]
                rows.append({"variant": variant, "kind": kind, "level": lv["level"], "dt": lv["dt"], "k_c": lv["stiffness"],
                             "change_mm": "" if ch is None else "%.6g" % (ch * 1e3), "twist_mm": tw, "top_z_mm": z,
                             "converged": summary["converged"] if lv is summary["levels"][-1] else ""})
        rows[-1]["kinds_gap_mm"] = gap(final["two-sided"], final["one-sided"])
    # Inverted rows at level 0.
    inv = {}
    with open(os.path.join(root, "lattice_inversion.csv")) as f:
        for r in csv.DictReader(f):
            if r["scene"] == "cylinder_press" and r["body"] == "layer" and r["axis"] == "z":
                inv[("springs", r["two_sided"])] = r
    with open(os.path.join(d, "inversion.csv")) as f:
        for r in csv.DictReader(f):
            if r["body"] == "layer" and r["axis"] == "z":
                inv[("bulk " + r["diagonals"], r["two_sided"])] = r
    with open(os.path.join(d, "inversion48.csv")) as f:
        for r in csv.DictReader(f):
            if r["body"] == "layer" and r["axis"] == "z":
                inv[(VARIANTS[2][0], r["two_sided"])] = r
    for variant in ["springs"] + [v for v, _s in VARIANTS]:
        for ts, kind in (("true", "two-sided"), ("false", "one-sided")):
            r = inv[(variant, ts)]
            rows.append({"variant": variant, "kind": "inversion " + kind, "inverted_rows": r["inverted_rows"],
                         "rows": r["rows"], "deepest_mm": r["deepest_mm"]})
    cols = ["variant", "kind", "level", "dt", "k_c", "change_mm", "twist_mm", "top_z_mm", "kinds_gap_mm", "converged",
            "inverted_rows", "rows", "deepest_mm"]
    out = os.path.join(root, "cylinder_bulk.csv")
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.5g" % v if isinstance(v, float) else ("" if v is None else v)) for k, v in
                        ((k, r.get(k)) for k in cols)})
    print("wrote %s (%d rows)" % (out, len(rows)))


if __name__ == "__main__":
    main()
