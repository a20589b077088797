#!/usr/bin/env python3
"""A worked ablation from Python (docs/python.md): the paper's voxel model on a bundled scene,
its constant contact force against its voxel size, each run's accuracy against its time per step,
beside the same scene with no contact force. Accuracy both ways: the deepest true penetration
CGAL finds (every `--every` steps) and the gap the force leaves between the surfaces at the end
(the smallest signed distance of a surface vertex to the other body's surface: a force that
pushes too early holds the bodies apart). Writes DIR/ablation.csv and DIR/ablation.png.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/ablation.py --out out/ablation
"""
import argparse
import csv
import os
import time

import harness


def one_run(scene, steps, every):
    """Steps the scene, measuring the exact references every `every` steps; returns the deepest
    penetration (m), the largest count of truly penetrating nodes, the nodes tunnelled and the gap
    (m) at the end, and the mean wall time of a step (us, measurement excluded)."""
    sim = harness.Simulation(scene)
    depth, pen, stepping = 0.0, 0, 0.0
    m = sim.measure(0)
    while sim.step_index < steps:
        n = min(every, steps - sim.step_index)
        t0 = time.perf_counter()
        sim.step(n)
        stepping += time.perf_counter() - t0
        m = sim.measure(0)
        depth = max(depth, m["max_depth"])
        pen = max(pen, m["true_pen_guest"] + m["true_pen_host"])
    return depth, pen, m["tunnelled_guest"] + m["tunnelled_host"], max(m["gap"], 0.0), 1e6 * stepping / steps


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="sphere_collision", help="scene file or bundled name")
    ap.add_argument("--forces", default="0.001,0.003,0.01", help="constant contact forces, N")
    ap.add_argument("--voxels", default="0.00390625,0.0078125,0.015625", help="voxel sizes, m (powers of two)")
    ap.add_argument("--steps", type=int, default=3000, help="steps per run")
    ap.add_argument("--every", type=int, default=50, help="steps between measurements")
    ap.add_argument("--out", required=True, help="output folder")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    base = harness.Scene.load(args.scene).with_(**{"contacts.0.detector": "voxel", "contacts.0.eliminator": "line",
                                                  "contacts.0.two_sided": False})
    points = [(0.0, "")] + [(float(f), float(v)) for v in args.voxels.split(",") for f in args.forces.split(",")]
    rows = []
    for f, v in points:
        edits = {"contacts.0.force": f}
        if v != "":
            edits["contacts.0.voxel_size"] = v
        d, p, t, gap, us = one_run(base.with_(**edits), args.steps, args.every)
        rows.append({"force": f, "voxel": v, "depth_max_mm": 1e3 * d, "pen_max": p, "tunnelled": t,
                     "gap_end_mm": 1e3 * gap, "step_us": us})
        print(f"force {f:g} N, voxel {'-' if v == '' else f'{1e3 * v:g} mm'}: deepest {1e3 * d:.3f} mm, {p} nodes "
              f"in at most, {t} tunnelled, gap at the end {1e3 * gap:.3f} mm, {us:.1f} us/step", flush=True)
    with open(os.path.join(args.out, "ablation.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    plot(rows, os.path.join(args.out, "ablation.png"), args)


def plot(rows, path, args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(7, 3.2), dpi=150, sharex=True)
    none = rows[0]
    for ax, key, label in ((axes[0], "depth_max_mm", "deepest true penetration, mm"),
                           (axes[1], "gap_end_mm", "gap left at the end, mm")):
        ax.axhline(none[key], color="0.5", ls="--", lw=1, label="no contact force")
        for v in sorted({r["voxel"] for r in rows[1:]}):
            pts = [r for r in rows[1:] if r["voxel"] == v]
            ax.plot([r["step_us"] for r in pts], [r[key] for r in pts], "o-", label=f"voxel {1e3 * v:g} mm")
            for r in pts:
                ax.annotate(f"{r['force']:g} N", (r["step_us"], r[key]), fontsize=5, xytext=(3, 3),
                            textcoords="offset points")
        ax.set_xlabel("time per step, us (one thread)")
        ax.set_ylabel(label)
    axes[0].legend(fontsize=6)
    fig.suptitle(f"{args.scene}: the voxel model, line rule, constant force, {args.steps} steps", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


if __name__ == "__main__":
    main()
