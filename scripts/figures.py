#!/usr/bin/env python3
"""Figures of the reproduction, from results/runs/* (see results/README.md).

Usage: figures.py [RESULTS_DIR]     (default: results; writes RESULTS_DIR/figures/*.png)

  snapshots_<scene>.png   both surfaces in 3D at four instants, line (top) and plane (bottom):
                          truly penetrating vertices marked (POINT_DATA of the frames), the voxel
                          region of that step drawn as a box (region_* columns of steps.csv)
  section_<scene>.png     implant scenes: cross-section y = 0 (triangles cut by the plane), the
                          rest state in grey, the tissue dome lifted by the implant
  timeseries_<scene>.png  true penetrations (guest, host), detected contacts, maximum residual
                          depth and contact force per step, line against plane
  episodes.png            how many steps a node stays truly penetrating, line against plane
Deterministic: fixed run order, no dates, fixed sizes and resolution.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import resultslib as rl  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

plt.rcParams.update({
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "figure.dpi": 100,
    "savefig.dpi": 110,
    "svg.hashsalt": "harness",
})
SAVE_META = {"Software": None}

HOST_COLOR = "#8fb3d9"
GUEST_COLOR = "#e8b27a"
PEN_GUEST = "#d62728"
PEN_HOST = "#6a0dad"
REGION_COLOR = "#2ca02c"
VIEW = {"sphere_collision": (22, -62), "cylinder_press": (24, -58), "implant_expansion": (28, -60)}


def save(fig, root, name):
    d = os.path.join(root, "figures")
    os.makedirs(d, exist_ok=True)
    fig.savefig(os.path.join(d, name), metadata=SAVE_META)
    plt.close(fig)
    print("figures: wrote %s" % os.path.join(d, name))


def by_scene(runs):
    out = {}
    for key, scene, title, force, elim, path in runs:
        out.setdefault(key, {"scene": scene, "title": title, "force": force, "runs": {}})
        out[key]["runs"][elim] = path
    return out


def box_edges(lo, hi):
    c = [[lo[0], lo[1], lo[2]], [hi[0], lo[1], lo[2]], [hi[0], hi[1], lo[2]], [lo[0], hi[1], lo[2]],
         [lo[0], lo[1], hi[2]], [hi[0], lo[1], hi[2]], [hi[0], hi[1], hi[2]], [lo[0], hi[1], hi[2]]]
    e = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    return [[c[a], c[b]] for a, b in e]


def load_frame(path, body, step):
    pts, tris, pen = rl.read_vtk(rl.frame_path(path, body, step))
    return np.array(pts, dtype=float), np.array(tris, dtype=int), (None if pen is None else np.array(pen))


def snapshot_figure(root, key, info):
    elims = [e for e in rl.ELIMINATORS if e in info["runs"]]
    if not elims:
        return
    first = info["runs"][elims[0]]
    summary = rl.load_summary(first)
    host, guest = rl.body_names(summary)
    steps = rl.snapshot_steps(summary)
    dt = float(summary["resolved_scene"]["time"]["dt"])
    # Data: frames and regions, and common limits over every panel.
    data = {}
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for e in elims:
        path = info["runs"][e]
        cols = rl.load_steps(path)
        for s in steps:
            fh = load_frame(path, host, s)
            fg = load_frame(path, guest, s)
            reg = rl.region_at(cols, s)
            k = rl.steps_row(cols, s)
            data[(e, s)] = (fh, fg, reg, cols["true_pen_guest"][k] if s > 0 else None,
                            cols["true_pen_host"][k] if s > 0 else None)
            for f in (fh, fg):
                lo = np.minimum(lo, f[0].min(axis=0))
                hi = np.maximum(hi, f[0].max(axis=0))
            if reg is not None:
                lo = np.minimum(lo, reg[0])
                hi = np.maximum(hi, reg[1])
    pad = 0.03 * (hi - lo).max()
    lo -= pad
    hi += pad
    elev, azim = VIEW.get(info["scene"], (25, -60))
    ncol = len(steps)
    fig = plt.figure(figsize=(3.3 * ncol, 3.4 * len(elims) + 0.6))
    for r, e in enumerate(elims):
        for c, s in enumerate(steps):
            ax = fig.add_subplot(len(elims), ncol, r * ncol + c + 1, projection="3d")
            (ph, th, penh), (pg, tg, peng), reg, tpg, tph = data[(e, s)]
            mm = 1000.0
            ax.add_collection3d(Poly3DCollection(ph[th] * mm, facecolor=HOST_COLOR, edgecolor="#4a6f96",
                                                 linewidths=0.08, alpha=0.35))
            ax.add_collection3d(Poly3DCollection(pg[tg] * mm, facecolor=GUEST_COLOR, edgecolor="#9a6a35",
                                                 linewidths=0.08, alpha=0.35))
            if reg is not None:
                ax.add_collection3d(Line3DCollection(np.array(box_edges(reg[0], reg[1])) * mm,
                                                     colors=REGION_COLOR, linewidths=0.9, linestyles="--"))
            measured = penh is not None or peng is not None
            for pts, pen, col, mk in ((pg, peng, PEN_GUEST, "o"), (ph, penh, PEN_HOST, "^")):
                if pen is not None and pen.sum() > 0:
                    q = pts[pen == 1] * mm
                    ax.scatter(q[:, 0], q[:, 1], q[:, 2], s=7, c=col, marker=mk, depthshade=False)
            ax.set_xlim(lo[0] * mm, hi[0] * mm)
            ax.set_ylim(lo[1] * mm, hi[1] * mm)
            ax.set_zlim(lo[2] * mm, hi[2] * mm)
            ax.set_box_aspect(tuple((hi - lo) / (hi - lo).max()))
            ax.view_init(elev=elev, azim=azim)
            ax.tick_params(labelsize=6, pad=0)
            ax.set_xlabel("x (mm)", fontsize=7, labelpad=-4)
            ax.set_ylabel("y (mm)", fontsize=7, labelpad=-4)
            ax.set_zlabel("z (mm)", fontsize=7, labelpad=-4)
            if measured:
                pen_txt = "penetrating: %d %s, %d %s" % (int(tpg or 0), guest, int(tph or 0), host)
            else:
                pen_txt = "rest state (not measured)"
            ax.set_title("%s, step %d (t = %.1f ms)\n%s" % (e, s, s * dt * 1000.0, pen_txt), fontsize=8)
    handles = [
        matplotlib.patches.Patch(facecolor=HOST_COLOR, edgecolor="#4a6f96", label="host: %s (voxel lists)" % host),
        matplotlib.patches.Patch(facecolor=GUEST_COLOR, edgecolor="#9a6a35", label="guest: %s (looked up)" % guest),
        matplotlib.lines.Line2D([], [], color=REGION_COLOR, ls="--", label="voxel region of the step"),
        matplotlib.lines.Line2D([], [], color=PEN_GUEST, marker="o", ls="", label="truly penetrating %s vertex" % guest),
        matplotlib.lines.Line2D([], [], color=PEN_HOST, marker="^", ls="", label="truly penetrating %s vertex" % host),
    ]
    fig.legend(handles=handles, loc="lower center", ncol=5, frameon=False)
    fig.suptitle("%s: snapshots, line eliminator (top) and plane eliminator (bottom); force %s"
                 % (info["title"], info["force"]), fontsize=10)
    fig.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.07, wspace=0.05, hspace=0.15)
    save(fig, root, "snapshots_%s.png" % key)


def section_segments(pts, tris, y0=0.0):
    """Segments (x, z) where the triangles cross the plane y = y0. A vertex on the plane counts
    as above it (a consistent tie rule: every crossing is found exactly once)."""
    d = pts[:, 1] - y0
    pos = d >= 0.0
    segs = []
    for t in tris:
        s = pos[t]
        if s.all() or (~s).all():
            continue
        q = []
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if pos[a] != pos[b]:
                u = d[a] / (d[a] - d[b])
                p = pts[a] + u * (pts[b] - pts[a])
                q.append((p[0], p[2]))
        if len(q) == 2:
            segs.append(q)
    return segs


def section_figure(root, key, info):
    elims = [e for e in rl.ELIMINATORS if e in info["runs"]]
    if not elims:
        return
    summary = rl.load_summary(info["runs"][elims[0]])
    host, guest = rl.body_names(summary)
    steps = rl.snapshot_steps(summary)
    dt = float(summary["resolved_scene"]["time"]["dt"])
    mm = 1000.0
    fig, axes = plt.subplots(len(elims), len(steps), figsize=(3.6 * len(steps), 2.3 * len(elims) + 0.9),
                             sharex=True, sharey=True, squeeze=False)
    rest = {}
    for e in elims:
        path = info["runs"][e]
        for b in (host, guest):
            p, t, _ = load_frame(path, b, 0)
            rest[(e, b)] = section_segments(p, t)
    colors = {host: "#1f5f9f", guest: "#b5651d"}
    for r, e in enumerate(elims):
        path = info["runs"][e]
        cols = rl.load_steps(path)
        for c, s in enumerate(steps):
            ax = axes[r][c]
            npen = 0
            for b in (host, guest):
                ax.add_collection(LineCollection(np.array(rest[(e, b)]) * mm, colors="#bbbbbb", linewidths=0.8))
            for b in (host, guest):
                p, t, pen = load_frame(path, b, s)
                segs = section_segments(p, t)
                if segs:
                    ax.add_collection(LineCollection(np.array(segs) * mm, colors=colors[b], linewidths=1.1))
                if pen is not None:
                    near = (pen == 1) & (np.abs(p[:, 1]) <= 0.0025)
                    npen += int(pen.sum())
                    if near.any():
                        ax.plot(p[near, 0] * mm, p[near, 2] * mm, "o" if b == guest else "^", ms=3,
                                color=PEN_GUEST if b == guest else PEN_HOST, ls="")
            reg = rl.region_at(cols, s)
            if reg is not None:
                ax.add_patch(matplotlib.patches.Rectangle((reg[0][0] * mm, reg[0][2] * mm), (reg[1][0] - reg[0][0]) * mm,
                                                          (reg[1][2] - reg[0][2]) * mm, fill=False, ls="--",
                                                          ec=REGION_COLOR, lw=0.8))
            ax.set_title("%s, step %d (t = %.1f ms), %d penetrating" % (e, s, s * dt * 1000.0, npen)
                         if s > 0 else "%s, step 0 (rest)" % e, fontsize=8)
            ax.set_aspect("equal")
            ax.autoscale_view()
            if r == len(elims) - 1:
                ax.set_xlabel("x (mm)")
            if c == 0:
                ax.set_ylabel("z (mm)")
            ax.grid(True, lw=0.3, alpha=0.5)
    handles = [
        matplotlib.lines.Line2D([], [], color=colors[guest], label="%s (guest) at y = 0" % guest),
        matplotlib.lines.Line2D([], [], color=colors[host], label="%s (host) at y = 0" % host),
        matplotlib.lines.Line2D([], [], color="#bbbbbb", label="rest state"),
        matplotlib.lines.Line2D([], [], color=REGION_COLOR, ls="--", label="voxel region"),
        matplotlib.lines.Line2D([], [], color=PEN_GUEST, marker="o", ls="", label="penetrating %s vertex, |y| <= 2.5 mm" % guest),
        matplotlib.lines.Line2D([], [], color=PEN_HOST, marker="^", ls="", label="penetrating %s vertex, |y| <= 2.5 mm" % host),
    ]
    fig.legend(handles=handles, loc="lower center", ncol=3, frameon=False)
    fig.suptitle("%s: cross-section y = 0, line (top) and plane (bottom); force %s"
                 % (info["title"], info["force"]), fontsize=10)
    fig.subplots_adjust(left=0.06, right=0.99, top=0.88, bottom=0.25, wspace=0.08, hspace=0.35)
    save(fig, root, "section_%s.png" % key)


def timeseries_figure(root, key, info):
    elims = [e for e in rl.ELIMINATORS if e in info["runs"]]
    if not elims:
        return
    summary = rl.load_summary(info["runs"][elims[0]])
    host, guest = rl.body_names(summary)
    fig, axes = plt.subplots(4, 1, figsize=(7.5, 8.6), sharex=True)
    for e in elims:
        path = info["runs"][e]
        cols = rl.load_steps(path)
        col = rl.ELIM_STYLE[e]["color"]
        t = np.array(cols["time"]) * 1000.0
        st, g = rl.measured(cols, "true_pen_guest")
        _, h = rl.measured(cols, "true_pen_host")
        _, dep = rl.measured(cols, "max_depth")
        tm = np.array(st, dtype=float) * float(summary["resolved_scene"]["time"]["dt"]) * 1000.0
        axes[0].plot(tm, g, color=col, lw=1.2, label="%s: %s (guest)" % (e, guest))
        axes[0].plot(tm, h, color=col, lw=1.0, ls="--", label="%s: %s (host)" % (e, host))
        axes[1].plot(t, [v if v is not None else np.nan for v in cols["contacts"]], color=col, lw=0.6,
                     label="%s" % e)
        axes[2].plot(tm, np.array(dep) * 1000.0, color=col, lw=1.1, label="%s" % e)
        axes[3].plot(t, [v if v is not None else np.nan for v in cols["force"]], color=col, lw=0.5,
                     label="%s" % e)
    axes[0].set_ylabel("truly penetrating\nvertices")
    axes[0].set_title("True penetrations (CGAL, every %d steps)" % int(summary["resolved_scene"]["references"]["every"]))
    axes[1].set_ylabel("detected contacts")
    axes[1].set_title("Contacts detected by the voxel model (guest vertices in occupied voxels), every step")
    axes[2].set_ylabel("max residual\ndepth (mm)")
    axes[2].set_title("Maximum residual depth over the penetrating vertices of both bodies")
    axes[3].set_ylabel("force per\ncontact (N)")
    axes[3].set_title("Largest penalty force of a contact (force setting: %s)" % info["force"])
    axes[3].set_xlabel("time (ms)")
    for ax in axes:
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.legend(loc="upper left", ncol=2, frameon=False)
    fig.suptitle("%s: line against plane eliminator" % info["title"], fontsize=10)
    fig.tight_layout()
    save(fig, root, "timeseries_%s.png" % key)


def episodes_figure(root, scenes):
    keys = [k for k, _s, _t, _f in rl.SCENES if k in scenes]
    if not keys:
        return
    n = len(keys)
    ncol = 2
    nrow = (n + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(10, 3.2 * nrow), squeeze=False)
    edges = [5, 15, 35, 75, 155, 315, 635, 1275, 2555]
    for i, key in enumerate(keys):
        ax = axes[i // ncol][i % ncol]
        info = scenes[key]
        elims = [e for e in rl.ELIMINATORS if e in info["runs"]]
        width = 0.38
        for j, e in enumerate(elims):
            ep = rl.load_episodes(info["runs"][e])
            steps = sorted(r["steps"] for r in ep)
            nopen = sum(r["open"] for r in ep)
            counts, _ = np.histogram(steps, bins=edges)
            x = np.arange(len(counts)) + (j - 0.5) * width
            med = rl.nearest_rank(steps, 50)
            lab = "%s: %d episodes, median %s steps, %d open" % (e, len(steps), "-" if med is None else med, nopen)
            ax.bar(x, counts, width=width, color=rl.ELIM_STYLE[e]["color"], alpha=0.85, label=lab)
        ax.set_xticks(np.arange(len(edges) - 1))
        ax.set_xticklabels(["%d-%d" % (edges[k] + 5, edges[k + 1] - 5) for k in range(len(edges) - 1)],
                           rotation=30, fontsize=7)
        ax.set_xlabel("episode length (simulation steps; measured every 10)")
        ax.set_ylabel("episodes (vertices)")
        ax.set_title(info["title"])
        ax.legend(loc="upper right", frameon=False, fontsize=7)
        ax.grid(True, axis="y", lw=0.3, alpha=0.6)
    for i in range(n, nrow * ncol):
        axes[i // ncol][i % ncol].axis("off")
    fig.suptitle("How long a vertex stays truly penetrating (episodes of consecutive measured steps), "
                 "line against plane", fontsize=10)
    fig.tight_layout()
    save(fig, root, "episodes.png")


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    runs = rl.existing_runs(root)
    if not runs:
        sys.exit("figures: no runs under %s" % rl.runs_dir(root))
    scenes = by_scene(runs)
    for key, _scene, _title, _force in rl.SCENES:
        if key not in scenes:
            continue
        info = scenes[key]
        snapshot_figure(root, key, info)
        if info["scene"] == "implant_expansion":
            section_figure(root, key, info)
        timeseries_figure(root, key, info)
    episodes_figure(root, scenes)


if __name__ == "__main__":
    main()
