#!/usr/bin/env python3
"""Figures of the reproduction, from results/runs/* (see results/README.md).

Usage: figures.py [RESULTS_DIR]     (default: results; writes RESULTS_DIR/figures/*.png)

  snapshots_<scene>.png   both surfaces in 3D at four instants, line (top) and plane (bottom):
                          truly penetrating vertices marked (POINT_DATA of the frames), the voxel
                          region of that step drawn as a box (region_* columns of steps.csv)
  section_<scene>.png     cross-section (triangles cut by a plane: sphere z = 0, cylinder x = 0,
                          implant y = 0 showing the tissue dome lifted by the implant), the rest
                          state in grey
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
# Surface opacity (host, guest): the implant lies under the tissue, so the tissue is fainter.
ALPHA = {"implant_expansion": (0.55, 0.15)}
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
            ax.computed_zorder = False  # markers drawn over the translucent surfaces
            (ph, th, penh), (pg, tg, peng), reg, tpg, tph = data[(e, s)]
            mm = 1000.0
            ah, ag = ALPHA.get(info["scene"], (0.35, 0.35))
            ax.add_collection3d(Poly3DCollection(ph[th] * mm, facecolor=HOST_COLOR, edgecolor="#4a6f96",
                                                 linewidths=0.08, alpha=ah))
            ax.add_collection3d(Poly3DCollection(pg[tg] * mm, facecolor=GUEST_COLOR, edgecolor="#9a6a35",
                                                 linewidths=0.08, alpha=ag))
            if reg is not None:
                ax.add_collection3d(Line3DCollection(np.array(box_edges(reg[0], reg[1])) * mm,
                                                     colors=REGION_COLOR, linewidths=0.9, linestyles="--"))
            measured = penh is not None or peng is not None
            for pts, pen, col, mk in ((pg, peng, PEN_GUEST, "o"), (ph, penh, PEN_HOST, "^")):
                if pen is not None and pen.sum() > 0:
                    q = pts[pen == 1] * mm
                    ax.scatter(q[:, 0], q[:, 1], q[:, 2], s=7, c=col, marker=mk, depthshade=False, zorder=10)
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
                pen_txt = "penetrating nodes: %d %s, %d %s" % (int(tpg or 0), guest, int(tph or 0), host)
            else:
                pen_txt = "rest state (not measured)"
            ax.set_title("%s, step %d (t = %.1f ms)\n%s" % (e, s, s * dt * 1000.0, pen_txt), fontsize=8)
    handles = [
        matplotlib.patches.Patch(facecolor=HOST_COLOR, edgecolor="#4a6f96", label="host: %s (voxel lists)" % host),
        matplotlib.patches.Patch(facecolor=GUEST_COLOR, edgecolor="#9a6a35", label="guest: %s (looked up)" % guest),
        matplotlib.lines.Line2D([], [], color=REGION_COLOR, ls="--", label="voxel region of the step"),
        matplotlib.lines.Line2D([], [], color=PEN_GUEST, marker="o", ls="", label="truly penetrating %s surface vertex" % guest),
        matplotlib.lines.Line2D([], [], color=PEN_HOST, marker="^", ls="", label="truly penetrating %s surface vertex" % host),
    ]
    fig.legend(handles=handles, loc="lower center", ncol=5, frameon=False)
    fig.suptitle("%s: snapshots, line eliminator (top) and plane eliminator (bottom); force %s"
                 % (info["title"], info["force"]), fontsize=10)
    fig.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.07, wspace=0.05, hspace=0.15)
    save(fig, root, "snapshots_%s.png" % key)


# Cross-section of each scene: (axis normal to the plane, its value, in-plane axes (h, v)).
SECTION = {
    "sphere_collision": (2, 0.0, (0, 1)),   # z = 0: the contact seen from above
    "cylinder_press": (0, 0.0, (1, 2)),     # x = 0: across the cylinder's axis
    "implant_expansion": (1, 0.0, (0, 2)),  # y = 0: through the implant's centre
}
AXIS = "xyz"


def section_segments(pts, tris, axis, value):
    """Segments (in-plane point pairs, 3D) where the triangles cross the plane x_axis = value.
    A vertex on the plane counts as above it (a consistent tie rule: every crossing is found
    exactly once)."""
    d = pts[:, axis] - value
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
                q.append(pts[a] + u * (pts[b] - pts[a]))
        if len(q) == 2:
            segs.append(q)
    return np.array(segs).reshape(-1, 2, 3)


def mean_edge(pts, tris):
    e = np.concatenate([pts[tris[:, 1]] - pts[tris[:, 0]], pts[tris[:, 2]] - pts[tris[:, 1]],
                        pts[tris[:, 0]] - pts[tris[:, 2]]])
    return float(np.sqrt((e * e).sum(axis=1)).mean())


def section_figure(root, key, info):
    elims = [e for e in rl.ELIMINATORS if e in info["runs"]]
    if not elims or info["scene"] not in SECTION:
        return
    axis, value, (hx, vx) = SECTION[info["scene"]]
    summary = rl.load_summary(info["runs"][elims[0]])
    host, guest = rl.body_names(summary)
    steps = rl.snapshot_steps(summary)
    dt = float(summary["resolved_scene"]["time"]["dt"])
    mm = 1000.0
    rest = {}
    slab = {}
    for e in elims:
        path = info["runs"][e]
        for b in (host, guest):
            p, t, _ = load_frame(path, b, 0)
            rest[(e, b)] = section_segments(p, t, axis, value)
            slab[b] = 0.5 * mean_edge(p, t)
    # Panel shape from the data: the in-plane extent of every section shown.
    ext_h = ext_v = 0.0
    lo_h = lo_v = np.inf
    hi_h = hi_v = -np.inf
    frames = {}
    for e in elims:
        path = info["runs"][e]
        for s in steps:
            for b in (host, guest):
                p, t, pen = load_frame(path, b, s)
                seg = section_segments(p, t, axis, value)
                frames[(e, s, b)] = (p, seg, pen)
                if len(seg):
                    lo_h, hi_h = min(lo_h, seg[:, :, hx].min()), max(hi_h, seg[:, :, hx].max())
                    lo_v, hi_v = min(lo_v, seg[:, :, vx].min()), max(hi_v, seg[:, :, vx].max())
        cols = rl.load_steps(path)
        for s in steps:
            reg = rl.region_at(cols, s)
            if reg is not None:
                lo_h, hi_h = min(lo_h, reg[0][hx]), max(hi_h, reg[1][hx])
                lo_v, hi_v = min(lo_v, reg[0][vx]), max(hi_v, reg[1][vx])
    ext_h, ext_v = hi_h - lo_h, hi_v - lo_v
    panel_w = 3.6
    panel_h = (panel_w - 0.5) * ext_v / ext_h + 1.0
    fig, axes = plt.subplots(len(elims), len(steps), figsize=(panel_w * len(steps), panel_h * len(elims) + 1.2),
                             sharex=True, sharey=True, squeeze=False)
    colors = {host: "#1f5f9f", guest: "#b5651d"}
    for r, e in enumerate(elims):
        path = info["runs"][e]
        cols = rl.load_steps(path)
        for c, s in enumerate(steps):
            ax = axes[r][c]
            npen = 0
            for b in (host, guest):
                seg = rest[(e, b)]
                if len(seg):
                    ax.add_collection(LineCollection(seg[:, :, [hx, vx]] * mm, colors="#bbbbbb", linewidths=0.8))
            for b in (host, guest):
                p, seg, pen = frames[(e, s, b)]
                if len(seg):
                    ax.add_collection(LineCollection(seg[:, :, [hx, vx]] * mm, colors=colors[b], linewidths=1.1))
                if pen is not None:
                    near = (pen == 1) & (np.abs(p[:, axis] - value) <= slab[b])
                    npen += int(pen.sum())
                    if near.any():
                        ax.plot(p[near, hx] * mm, p[near, vx] * mm, "o" if b == guest else "^", ms=3,
                                color=PEN_GUEST if b == guest else PEN_HOST, ls="")
            reg = rl.region_at(cols, s)
            if reg is not None:
                ax.add_patch(matplotlib.patches.Rectangle((reg[0][hx] * mm, reg[0][vx] * mm),
                                                          (reg[1][hx] - reg[0][hx]) * mm,
                                                          (reg[1][vx] - reg[0][vx]) * mm, fill=False, ls="--",
                                                          ec=REGION_COLOR, lw=0.8))
            if s > 0:
                ax.set_title("%s, step %d (t = %.1f ms)\n%d penetrating surface vertices" % (e, s, s * dt * 1000.0, npen),
                             fontsize=8)
            else:
                ax.set_title("%s, step 0 (rest)" % e, fontsize=8)
            ax.set_aspect("equal")
            ax.autoscale_view()
            if r == len(elims) - 1:
                ax.set_xlabel("%s (mm)" % AXIS[hx])
            if c == 0:
                ax.set_ylabel("%s (mm)" % AXIS[vx])
            ax.grid(True, lw=0.3, alpha=0.5)
    handles = [
        matplotlib.lines.Line2D([], [], color=colors[guest], label="%s (guest)" % guest),
        matplotlib.lines.Line2D([], [], color=colors[host], label="%s (host)" % host),
        matplotlib.lines.Line2D([], [], color="#bbbbbb", label="rest state (step 0)"),
        matplotlib.lines.Line2D([], [], color=REGION_COLOR, ls="--", label="voxel region of the step"),
        matplotlib.lines.Line2D([], [], color=PEN_GUEST, marker="o", ls="",
                                label="penetrating %s vertex within %.1f mm of the plane" % (guest, slab[guest] * mm)),
        matplotlib.lines.Line2D([], [], color=PEN_HOST, marker="^", ls="",
                                label="penetrating %s vertex within %.1f mm of the plane" % (host, slab[host] * mm)),
    ]
    fig.legend(handles=handles, loc="lower center", ncol=3, frameon=False)
    fig.suptitle("%s: cross-section %s = %g mm, line (top) and plane (bottom); force %s"
                 % (info["title"], AXIS[axis], value * mm, info["force"]), fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
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
    axes[0].set_ylabel("truly penetrating\nnodes")
    axes[0].set_title("True penetrations (CGAL, every %d steps)" % int(summary["resolved_scene"]["references"]["every"]))
    axes[1].set_ylabel("detected contacts")
    axes[1].set_title("Contacts detected by the voxel model (guest nodes in occupied voxels), every step")
    axes[2].set_ylabel("max residual\ndepth (mm)")
    axes[2].set_title("Maximum residual depth over the penetrating nodes of both bodies")
    axes[3].set_ylabel("force per\ncontact (N)")
    axes[3].set_title("Largest penalty force of a contact (force setting: %s)" % info["force"])
    axes[3].set_xlabel("time (ms)")
    for ax in axes:
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.legend(loc="best", ncol=2, frameon=True, framealpha=0.8)
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
    longest = 10
    for info in scenes.values():
        for path in info["runs"].values():
            longest = max([longest] + [r["steps"] for r in rl.load_episodes(path)])
    edges = [5]
    while edges[-1] < longest:
        edges.append(10 * 2 ** len(edges) - 5)  # 5, 15, 35, 75, ...: bins of 10, 20-30, 40-70, ...
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
        ax.set_xticklabels([("%d-%d" % (edges[k] + 5, edges[k + 1] - 5)) if edges[k + 1] - edges[k] > 10
                            else "%d" % (edges[k] + 5) for k in range(len(edges) - 1)],
                           rotation=30, fontsize=7)
        ax.set_xlabel("episode length (simulation steps; measured every 10)")
        ax.set_ylabel("number of episodes")
        ax.set_title(info["title"])
        ax.legend(loc="best", frameon=True, fontsize=7)
        ax.grid(True, axis="y", lw=0.3, alpha=0.6)
    for i in range(n, nrow * ncol):
        axes[i // ncol][i % ncol].axis("off")
    fig.suptitle("How long a node stays truly penetrating (episodes of consecutive measured steps), "
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
        section_figure(root, key, info)
        timeseries_figure(root, key, info)
    episodes_figure(root, scenes)


if __name__ == "__main__":
    main()
