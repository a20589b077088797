#!/usr/bin/env python3
"""Why the cylinder's two-sided reference does not converge (docs/findings.md): the settled
surfaces of its levels 2 and 3 made again (results/cylinder_levels/run.sh: at the scene's settling
tolerance and at 1e-6), the final level (results/references/cylinder_press) and the one-sided
reference compared -> results/cylinder_levels.csv.

Rows of kind "change": between two settled states, per body, the largest node displacement, the
best rigid motion between them (Kabsch: its translation of the body's centre and its angle) and the
largest displacement left after removing it. Rows of kind "row": the layer's top row under the
cylinder's axis (start y = 0, z = 20 mm, x from -25 to 25 mm): its sideways offset y (mm) per node.
Usage: scripts/cylinder_levels.py [RESULTS]   (default results)
"""
import csv
import math
import os
import sys

import numpy as np

from harness_results import reader


def load(path):
    bodies = {}
    with reader.open_text(os.path.join(path, "surfaces.csv")) as f:  # plain or gzipped
        for r in csv.DictReader(f):
            bodies.setdefault(r["body"], []).append([float(r[k]) for k in ("x", "y", "z", "x0", "y0", "z0")])
    return {k: np.array(v) for k, v in bodies.items()}


def rigid(p, q):
    """(R, t) of the best rigid motion q ~ R p + t (Kabsch)."""
    cp, cq = p.mean(0), q.mean(0)
    u, _, vt = np.linalg.svd((p - cp).T @ (q - cq))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    return r, cq - r @ cp


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    lv = os.path.join(root, "cylinder_levels")
    states = {"level 2, settled to 1e-5": os.path.join(lv, "l2_5"), "level 2, settled to 1e-6": os.path.join(lv, "l2_6"),
              "level 3, settled to 1e-5": os.path.join(lv, "l3_5"), "level 3, settled to 1e-6": os.path.join(lv, "l3_6"),
              "level 4 (the reference)": os.path.join(root, "references", "cylinder_press"),
              "one-sided reference": os.path.join(root, "references", "cylinder_press_one_sided")}
    s = {k: load(v) for k, v in states.items()}
    pairs = [("level 2, settled to 1e-5", "level 2, settled to 1e-6"), ("level 3, settled to 1e-5", "level 3, settled to 1e-6"),
             ("level 2, settled to 1e-5", "level 3, settled to 1e-5"), ("level 3, settled to 1e-5", "level 4 (the reference)")]
    rows = []
    for a, b in pairs:
        for body in s[a]:
            p, q = s[a][body][:, :3], s[b][body][:, :3]
            r, t = rigid(p, q)
            left = np.linalg.norm(q - (p @ r.T + t), axis=1)
            ang = math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(r) - 1) / 2))))
            rows.append({"kind": "change", "from": a, "to": b, "body": body,
                         "max_change_mm": "%.5g" % (1e3 * np.linalg.norm(q - p, axis=1).max()),
                         "rigid_translation_mm": "%.4g" % (1e3 * np.linalg.norm(t + (r - np.eye(3)) @ p.mean(0))),
                         "rigid_angle_deg": "%.4g" % ang, "max_after_rigid_mm": "%.5g" % (1e3 * left.max())})
    for name, st in s.items():
        lay = st["layer"]
        sel = (np.abs(lay[:, 4]) < 1e-9) & (np.abs(lay[:, 5] - 0.02) < 1e-9) & (np.abs(lay[:, 3]) < 0.026)
        for x0, y in sorted(zip(lay[sel, 3], lay[sel, 1])):
            rows.append({"kind": "row", "from": name, "body": "layer", "x0_mm": "%g" % (1e3 * x0),
                         "y_mm": "%.4g" % (1e3 * y)})
    cols = ["kind", "from", "to", "body", "max_change_mm", "rigid_translation_mm", "rigid_angle_deg",
            "max_after_rigid_mm", "x0_mm", "y_mm"]
    out = os.path.join(root, "cylinder_levels.csv")
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, cols)
        w.writeheader()
        for r in rows:
            w.writerow({c: r.get(c, "") for c in cols})
    print("cylinder_levels.py: wrote %s" % out, file=sys.stderr)


if __name__ == "__main__":
    main()
