"""The figures of the runs (scripts/figures.py is the command line), from results/runs/* (see
results/README.md), written as RESULTS_DIR/figures/<name>.{pdf,png}:

  snapshots_<scene>   both surfaces in 3D at four instants, line (top) and plane (bottom):
                      truly penetrating vertices marked (POINT_DATA of the frames), the voxel
                      region of that step drawn as a box (region_* columns of steps.csv)
  section_<scene>     cross-section (triangles cut by a plane: SECTION), the rest state in grey
  timeseries_<scene>  true penetrations (guest, host), detected contacts, maximum residual
                      depth and contact force per step, line against plane
  episodes            how many steps a node stays truly penetrating, line against plane
Each figure is drawn at the size paper/main.tex prints it (style.TEXT or style.HALF) and written by
style.save. Deterministic: fixed run order, no dates, fixed sizes and resolution.
"""

import os

from . import reader, rules, runs, style

plt = style.pyplot()
import matplotlib  # after style.pyplot(), which sets the backend
import matplotlib.lines
import matplotlib.patches
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

HOST_COLOR = "#8fb3d9"
GUEST_COLOR = "#e8b27a"
PEN_GUEST = "#D55E00"
PEN_HOST = "#000000"
REGION_COLOR = "#009E73"
# Surface opacity (host, guest): the implant lies under the tissue, so the tissue is fainter.
ALPHA = {"implant_expansion": (0.55, 0.15)}
VIEW = {"sphere_collision": (22, -62), "cylinder_press": (24, -58), "implant_expansion": (28, -60)}
MM = 1000.0  # the figures' unit: mm


def save(fig, root, name, width):
    style.save(fig, os.path.join(root, "figures", name), width=width)


def box_edges(lo, hi):
    c = [[lo[0], lo[1], lo[2]], [hi[0], lo[1], lo[2]], [hi[0], hi[1], lo[2]], [lo[0], hi[1], lo[2]],
         [lo[0], lo[1], hi[2]], [hi[0], lo[1], hi[2]], [hi[0], hi[1], hi[2]], [lo[0], hi[1], hi[2]]]
    e = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    return [[c[a], c[b]] for a, b in e]


def load_frame(path, body, step):
    pts, tris, pen = runs.read_vtk(runs.frame_path(path, body, step))
    return np.array(pts, dtype=float), np.array(tris, dtype=int), (None if pen is None else np.array(pen))


def run_eliminators(info):
    """The eliminators of a run setting that were run, in runs.ELIMINATORS' order."""
    return [e for e in runs.ELIMINATORS if e in info["runs"]]


# ---------------------------------------------------------------------------------------------
# snapshots_<scene>
def snapshot_data(info, elims, steps, host, guest):
    """({(eliminator, step): (host frame, guest frame, region, true_pen_guest, true_pen_host)}, lo, hi):
    the frames and regions of every panel and the common limits over them, padded by 3 %."""
    data = {}
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for e in elims:
        path = info["runs"][e]
        cols = reader.load_steps(path)
        for s in steps:
            fh = load_frame(path, host, s)
            fg = load_frame(path, guest, s)
            reg = runs.region_at(cols, s)
            k = runs.steps_row(cols, s)
            pen = [cols[c][k] if s > 0 and reader.present(cols[c][k]) else None
                   for c in ("true_pen_guest", "true_pen_host")]
            data[(e, s)] = (fh, fg, reg, pen[0], pen[1])
            for f in (fh, fg):
                lo = np.minimum(lo, f[0].min(axis=0))
                hi = np.maximum(hi, f[0].max(axis=0))
            if reg is not None:
                lo = np.minimum(lo, reg[0])
                hi = np.maximum(hi, reg[1])
    pad = 0.03 * (hi - lo).max()
    lo -= pad
    hi += pad
    return data, lo, hi


def view_aspect(lo, hi, elev, azim):
    """A row's height over a panel's width: the height over the width of the scene's box seen from
    (elev, azim) (orthographic), between 0.45 and 1, so that flat scenes leave no empty band."""
    ea, aa = np.radians(elev), np.radians(azim)
    box = (hi - lo) / (hi - lo).max()
    corners = np.array([[x, y, z] for x in (0, box[0]) for y in (0, box[1]) for z in (0, box[2])])
    sx = -np.sin(aa) * corners[:, 0] + np.cos(aa) * corners[:, 1]
    sy = (-np.cos(aa) * corners[:, 0] - np.sin(aa) * corners[:, 1]) * np.sin(ea) + np.cos(ea) * corners[:, 2]
    return min(1.0, max(0.45, 0.9 * np.ptp(sy) / np.ptp(sx)))


def snapshot_surfaces(ax, d, alpha):
    """One panel's surfaces (rasterised), its voxel region and its truly penetrating vertices;
    whether the frames recorded penetration."""
    ax.computed_zorder = False  # markers drawn over the translucent surfaces
    (ph, th, penh), (pg, tg, peng), reg, _tpg, _tph = d
    ah, ag = alpha
    for pts, tri, fc, ec, al in ((ph, th, HOST_COLOR, "#4a6f96", ah), (pg, tg, GUEST_COLOR, "#9a6a35", ag)):
        pc = Poly3DCollection(pts[tri] * MM, facecolor=fc, edgecolor=ec, linewidths=0.05, alpha=al)
        pc.set_rasterized(True)  # thousands of triangles: an image inside the PDF
        ax.add_collection3d(pc)
    if reg is not None:
        ax.add_collection3d(Line3DCollection(np.array(box_edges(reg[0], reg[1])) * MM,
                                             colors=REGION_COLOR, linewidths=0.8, linestyles="--"))
    measured = penh is not None or peng is not None
    for pts, pen, col, mk in ((pg, peng, PEN_GUEST, "o"), (ph, penh, PEN_HOST, "^")):
        if pen is not None and pen.sum() > 0:
            q = pts[pen == 1] * MM
            ax.scatter(q[:, 0], q[:, 1], q[:, 2], s=4, c=col, marker=mk, depthshade=False, zorder=10,
                       linewidths=0)
    return measured


def scale_bar(ax, lo, bar, ext):
    """A bar of `bar` mm at the panel's lower corner, with its length written under it."""
    x0, y0, z0 = lo * MM
    ax.plot([x0, x0 + bar], [y0, y0], [z0, z0], color="k", lw=1.2, zorder=11)
    ax.text(x0 + bar / 2, y0, z0 - 0.06 * ext.max(), "%g mm" % bar, fontsize=style.SMALL, ha="center",
            va="top", zorder=11)


def snapshot_view(ax, lo, hi, elev, azim):
    """The panel's limits, box aspect and view; no axes."""
    ax.set_xlim(lo[0] * MM, hi[0] * MM)
    ax.set_ylim(lo[1] * MM, hi[1] * MM)
    ax.set_zlim(lo[2] * MM, hi[2] * MM)
    ax.set_box_aspect(tuple((hi - lo) / (hi - lo).max()), zoom=1.2)
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()


def snapshot_key(host, guest):
    """The snapshots' key."""
    return [
        matplotlib.patches.Patch(facecolor=HOST_COLOR, edgecolor="#4a6f96", label="host: %s (voxel lists)" % host),
        matplotlib.patches.Patch(facecolor=GUEST_COLOR, edgecolor="#9a6a35", label="guest: %s (looked up)" % guest),
        matplotlib.lines.Line2D([], [], color=REGION_COLOR, ls="--", label="voxel region of the step"),
        matplotlib.lines.Line2D([], [], color=PEN_GUEST, marker="o", ms=3, ls="",
                                label="truly penetrating %s vertex" % guest),
        matplotlib.lines.Line2D([], [], color=PEN_HOST, marker="^", ms=3, ls="",
                                label="truly penetrating %s vertex" % host),
        matplotlib.lines.Line2D([], [], ls="", label="counts: truly penetrating nodes of each body"),
    ]


def snapshot_figure(root, key, info):
    """Printed at the text width: a row of panels per eliminator (named at its left), the instants
    above the columns, the key below. Orthographic views without axes; a scale bar in the first
    column gives the size."""
    elims = run_eliminators(info)
    if not elims:
        return
    summary = reader.load_summary(info["runs"][elims[0]])
    host, guest = reader.contact_bodies(summary)
    steps = runs.snapshot_steps(summary)
    dt = reader.scene_dt(summary)
    data, lo, hi = snapshot_data(info, elims, steps, host, guest)
    elev, azim = VIEW.get(info["scene"], (25, -60))
    side = 0.2
    panel = (style.TEXT - side) / len(steps)
    rowh = panel * view_aspect(lo, hi, elev, azim)
    titles = [0.30] + [0.16] * (len(elims) - 1)  # two lines of title above the first row, one after
    foot = 0.36
    height = sum(titles) + rowh * len(elims) + foot
    fig = plt.figure(figsize=(style.TEXT, height))
    ext = (hi - lo) * MM
    bar = [b * 10 ** k for k in range(-1, 4) for b in (1, 2, 5) if b * 10 ** k <= ext[0] / 2.5][-1]
    top = height
    for r, e in enumerate(elims):
        top -= titles[r]
        fig.text(0.04 / style.TEXT, (top - rowh / 2) / height, e, rotation=90, ha="left", va="center",
                 fontweight="bold")
        for c, s in enumerate(steps):
            ax = fig.add_axes([(side + c * panel) / style.TEXT, (top - rowh) / height, panel / style.TEXT,
                               rowh / height], projection="3d", proj_type="ortho")
            measured = snapshot_surfaces(ax, data[(e, s)], ALPHA.get(info["scene"], (0.35, 0.35)))
            if c == 0:
                scale_bar(ax, lo, bar, ext)
            snapshot_view(ax, lo, hi, elev, azim)
            tpg, tph = data[(e, s)][3:]
            if measured:
                txt = "%d %s, %d %s" % (int(tpg or 0), guest, int(tph or 0), host)
            else:
                txt = "rest state"
            ax.text2D(0.5, 1.0, ("step %d, t = %.0f ms\n" % (s, s * dt * 1000.0) if r == 0 else "") + txt,
                      transform=ax.transAxes, ha="center", va="bottom", fontsize=style.SMALL)
        top -= rowh
    fig.legend(handles=snapshot_key(host, guest), loc="lower center", ncol=3, frameon=False, fontsize=style.SMALL,
               bbox_to_anchor=(0.5, 0.0), columnspacing=1.2, handletextpad=0.5)
    save(fig, root, "snapshots_%s" % key, style.TEXT)


# ---------------------------------------------------------------------------------------------
# section_<scene>
# Cross-section of each scene: (axis normal to the plane, its value, in-plane axes (h, v)).
SECTION = {
    "sphere_collision": (2, 0.0, (0, 1)),   # z = 0: the contact seen from above
    "cylinder_press": (0, 0.0, (1, 2)),     # x = 0: across the cylinder's axis
    "implant_expansion": (1, 0.0, (0, 2)),  # y = 0: through the implant's centre
}
AXIS = "xyz"
SECTION_REST = "#bbbbbb"  # the rest state's sections


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


def section_rest(info, elims, bodies, axis, value):
    """({(eliminator, body): the rest state's section}, {body: half its mean edge: the slab around
    the plane in which a penetrating vertex is drawn})."""
    rest = {}
    slab = {}
    for e in elims:
        path = info["runs"][e]
        for b in bodies:
            p, t, _ = load_frame(path, b, 0)
            rest[(e, b)] = section_segments(p, t, axis, value)
            slab[b] = 0.5 * mean_edge(p, t)
    return rest, slab


def section_frames(info, elims, steps, bodies, axis, value, hx, vx):
    """({(eliminator, step, body): (points, section, penetrating)}, (lo_h, hi_h, lo_v, hi_v)): the
    sections shown and their in-plane extent (the voxel regions included)."""
    lo_h = lo_v = np.inf
    hi_h = hi_v = -np.inf
    frames = {}
    for e in elims:
        path = info["runs"][e]
        for s in steps:
            for b in bodies:
                p, t, pen = load_frame(path, b, s)
                seg = section_segments(p, t, axis, value)
                frames[(e, s, b)] = (p, seg, pen)
                if len(seg):
                    lo_h, hi_h = min(lo_h, seg[:, :, hx].min()), max(hi_h, seg[:, :, hx].max())
                    lo_v, hi_v = min(lo_v, seg[:, :, vx].min()), max(hi_v, seg[:, :, vx].max())
        cols = reader.load_steps(path)
        for s in steps:
            reg = runs.region_at(cols, s)
            if reg is not None:
                lo_h, hi_h = min(lo_h, reg[0][hx]), max(hi_h, reg[1][hx])
                lo_v, hi_v = min(lo_v, reg[0][vx]), max(hi_v, reg[1][vx])
    return frames, (lo_h, hi_h, lo_v, hi_v)


def section_panel(ax, rest, frames, reg, sec):
    """One panel: the rest state's sections in grey, the step's in the bodies' colours, the truly
    penetrating vertices near the plane, the voxel region; the penetrating vertices of both bodies
    (all of them, near the plane or not)."""
    axis, value, hx, vx, host, guest, colors, slab = sec
    npen = 0
    for b in (host, guest):
        seg = rest[b]
        if len(seg):
            ax.add_collection(LineCollection(seg[:, :, [hx, vx]] * MM, colors=SECTION_REST, linewidths=0.6))
    for b in (host, guest):
        p, seg, pen = frames[b]
        if len(seg):
            ax.add_collection(LineCollection(seg[:, :, [hx, vx]] * MM, colors=colors[b], linewidths=0.8))
        if pen is not None:
            near = (pen == 1) & (np.abs(p[:, axis] - value) <= slab[b])
            npen += int(pen.sum())
            if near.any():
                ax.plot(p[near, hx] * MM, p[near, vx] * MM, "o" if b == guest else "^", ms=2.2,
                        color=PEN_GUEST if b == guest else PEN_HOST, ls="", mew=0)
    if reg is not None:
        ax.add_patch(matplotlib.patches.Rectangle((reg[0][hx] * MM, reg[0][vx] * MM),
                                                  (reg[1][hx] - reg[0][hx]) * MM,
                                                  (reg[1][vx] - reg[0][vx]) * MM, fill=False, ls="--",
                                                  ec=REGION_COLOR, lw=0.7))
    return npen


def section_labels(ax, head, npen, s, last_row, ylabel, hx):
    """A panel's title (`head`: the instant, above the first row), ticks, axis labels (the x label
    on the last row, `ylabel` in the first column) and grid."""
    ax.set_title(head + ("%d penetrating vertices" % npen if s > 0 else "rest state"), fontsize=style.SMALL)
    ax.set_aspect("equal")
    ax.tick_params(labelsize=style.SMALL)
    ax.xaxis.set_major_locator(MaxNLocator(4))
    ax.yaxis.set_major_locator(MaxNLocator(4))
    if last_row:
        ax.set_xlabel("%s (mm)" % AXIS[hx], fontsize=style.SMALL)
    else:
        ax.tick_params(labelbottom=False)
    if ylabel is not None:
        ax.set_ylabel(ylabel, fontsize=style.SMALL)
    else:
        ax.tick_params(labelleft=False)
    ax.grid(True, lw=0.3, alpha=0.5)


def section_key(host, guest, colors, slab):
    """The sections' key."""
    return [
        matplotlib.lines.Line2D([], [], color=colors[guest], label="%s (guest)" % guest),
        matplotlib.lines.Line2D([], [], color=colors[host], label="%s (host)" % host),
        matplotlib.lines.Line2D([], [], color=SECTION_REST, label="rest state (step 0)"),
        matplotlib.lines.Line2D([], [], color=REGION_COLOR, ls="--", label="voxel region of the step"),
        matplotlib.lines.Line2D([], [], color=PEN_GUEST, marker="o", ms=3, ls="",
                                label="penetrating %s vertex within %.1f mm of the plane" % (guest, slab[guest] * MM)),
        matplotlib.lines.Line2D([], [], color=PEN_HOST, marker="^", ms=3, ls="",
                                label="penetrating %s vertex within %.1f mm of the plane" % (host, slab[host] * MM)),
    ]


def section_figure(root, key_name, info):
    """Printed at the text width: panels of equal scale (mm), sized from the sections' extent; a
    row per eliminator, the instants above the columns, the key in a row of its own below."""
    elims = run_eliminators(info)
    if not elims or info["scene"] not in SECTION:
        return
    axis, value, (hx, vx) = SECTION[info["scene"]]
    summary = reader.load_summary(info["runs"][elims[0]])
    host, guest = reader.contact_bodies(summary)
    steps = runs.snapshot_steps(summary)
    dt = reader.scene_dt(summary)
    rest, slab = section_rest(info, elims, (host, guest), axis, value)
    frames, (lo_h, hi_h, lo_v, hi_v) = section_frames(info, elims, steps, (host, guest), axis, value, hx, vx)
    ext_h, ext_v = hi_h - lo_h, hi_v - lo_v
    ncol = len(steps)
    panel_w = (style.TEXT - 0.55) / ncol
    panel_h = min(1.6, panel_w * ext_v / ext_h)
    height = len(elims) * (panel_h + 0.3) + 0.3 + 0.5
    fig = plt.figure(figsize=(style.TEXT, height), layout="constrained")
    gs = fig.add_gridspec(len(elims) + 1, ncol, height_ratios=[panel_h] * len(elims) + [0.42])
    axes = [[None] * ncol for _ in elims]
    for r in range(len(elims)):
        for c in range(ncol):
            axes[r][c] = fig.add_subplot(gs[r, c], sharex=axes[0][0], sharey=axes[0][0])
    colors = {host: "#1f5f9f", guest: "#b5651d"}
    sec = (axis, value, hx, vx, host, guest, colors, slab)
    for r, e in enumerate(elims):
        cols = reader.load_steps(info["runs"][e])
        for c, s in enumerate(steps):
            npen = section_panel(axes[r][c], {b: rest[(e, b)] for b in (host, guest)},
                                 {b: frames[(e, s, b)] for b in (host, guest)}, runs.region_at(cols, s), sec)
            head = ("step %d, t = %.0f ms\n" % (s, s * dt * 1000.0)) if r == 0 else ""
            section_labels(axes[r][c], head, npen, s, r == len(elims) - 1,
                           "%s\n%s (mm)" % (e, AXIS[vx]) if c == 0 else None, hx)
    axes[0][0].set_xlim((lo_h - 0.02 * ext_h) * MM, (hi_h + 0.02 * ext_h) * MM)
    axes[0][0].set_ylim((lo_v - 0.02 * ext_v) * MM, (hi_v + 0.02 * ext_v) * MM)
    key = fig.add_subplot(gs[len(elims), :])
    key.axis("off")
    key.legend(handles=section_key(host, guest, colors, slab), loc="center", ncol=3, frameon=False,
               fontsize=style.SMALL, borderaxespad=0.0, columnspacing=1.2)
    save(fig, root, "section_%s" % key_name, style.TEXT)


# ---------------------------------------------------------------------------------------------
# timeseries_<scene>
def timeseries_figure(root, key_name, info):
    """Printed in a minipage of half the text width (style.HALF), two to a page row."""
    elims = run_eliminators(info)
    if not elims:
        return
    summary = reader.load_summary(info["runs"][elims[0]])
    host, guest = reader.contact_bodies(summary)
    every = reader.measure_every(summary)
    fig = plt.figure(figsize=(style.HALF, 4.7), layout="constrained")
    gs = fig.add_gridspec(5, 1, height_ratios=[0.36, 1, 1, 1, 1])
    axes = [fig.add_subplot(gs[k + 1]) for k in range(4)]
    for ax in axes[1:]:
        ax.sharex(axes[0])
    for e in elims:
        path = info["runs"][e]
        cols = reader.load_steps(path)
        col = style.ELIM_STYLE[e]["color"]
        t = np.array(cols["time"]) * 1000.0
        st, g = reader.measured(cols, "true_pen_guest")
        _, h = reader.measured(cols, "true_pen_host")
        _, dep = reader.measured(cols, "max_depth")
        tm = np.array(st, dtype=float) * reader.scene_dt(summary) * 1000.0
        axes[0].plot(tm, g, color=col, lw=1.0)
        axes[0].plot(tm, h, color=col, lw=0.8, ls="--")
        axes[1].plot(t, cols["contacts"], color=col, lw=0.5)  # NaN (a gap) where not recorded
        axes[2].plot(tm, np.array(dep) * 1000.0, color=col, lw=0.9)
        axes[3].plot(t, cols["force"], color=col, lw=0.5)
    titles = ["truly penetrating nodes (CGAL, every %d steps)" % every,
              "contacts the voxel model detects",
              "largest residual depth, both bodies",
              "largest penalty force of a contact"]
    ylabels = ["nodes", "contacts", "depth (mm)", "force (N)"]
    for ax, ti, yl in zip(axes, titles, ylabels):
        ax.set_title(ti, fontsize=style.SMALL, loc="left", pad=2)
        ax.set_ylabel(yl)
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.yaxis.set_major_locator(MaxNLocator(4))
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xlabel("time (ms)")
    key = fig.add_subplot(gs[0])
    key.axis("off")
    handles = [matplotlib.lines.Line2D([], [], color=style.ELIM_STYLE[e]["color"], label=e) for e in elims]
    handles += [matplotlib.lines.Line2D([], [], color="0.3", lw=1.0, label="%s (guest)" % guest),
                matplotlib.lines.Line2D([], [], color="0.3", lw=0.8, ls="--", label="%s (host)" % host)]
    key.legend(handles=handles, loc="center", ncol=2, frameon=False, fontsize=style.SMALL, borderaxespad=0.0,
               columnspacing=1.0, handlelength=1.8)
    save(fig, root, "timeseries_%s" % key_name, style.HALF)


# ---------------------------------------------------------------------------------------------
# episodes
def episodes_figure(root, scenes):
    """Printed at the text width: a panel per run setting, two to a row."""
    keys = [k for k, _s, _t, _f in runs.SCENES if k in scenes]
    if not keys:
        return
    n = len(keys)
    ncol = 2
    nrow = (n + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(style.TEXT, 1.95 * nrow + 0.1), squeeze=False, layout="constrained")
    longest = 10
    for info in scenes.values():
        for path in info["runs"].values():
            longest = max([longest] + [r["steps"] for r in reader.load_episodes(path)])
    edges = [5]
    while edges[-1] < longest:
        edges.append(10 * 2 ** len(edges) - 5)  # 5, 15, 35, 75, ...: bins of 10, 20-30, 40-70, ...
    for i, key in enumerate(keys):
        ax = axes[i // ncol][i % ncol]
        info = scenes[key]
        elims = run_eliminators(info)
        width = 0.38
        for j, e in enumerate(elims):
            ep = reader.load_episodes(info["runs"][e])
            steps = sorted(r["steps"] for r in ep)
            nopen = sum(r["open"] for r in ep)
            counts, _ = np.histogram(steps, bins=edges)
            x = np.arange(len(counts)) + (j - 0.5) * width
            med = rules.nearest_rank(steps, 50)
            lab = "%s: %d episodes, median %s steps, %d open" % (e, len(steps), "-" if med is None else med, nopen)
            ax.bar(x, counts, width=width, color=style.ELIM_STYLE[e]["color"], label=lab)
        ax.set_xticks(np.arange(len(edges) - 1))
        ax.set_xticklabels([("%d-%d" % (edges[k] + 5, edges[k + 1] - 5)) if edges[k + 1] - edges[k] > 10
                            else "%d" % (edges[k] + 5) for k in range(len(edges) - 1)],
                           rotation=40, ha="right", rotation_mode="anchor", fontsize=style.SMALL)
        ax.tick_params(axis="y", labelsize=style.SMALL)
        if i // ncol == nrow - 1 or i + ncol >= n:
            ax.set_xlabel("episode length (steps; measured every %d)" % reader.measure_every(
                reader.load_summary(info["runs"][elims[0]])))
        if i % ncol == 0:
            ax.set_ylabel("episodes")
        ax.set_title(info["title"])
        ax.set_ylim(0, 1.55 * max(1, ax.get_ylim()[1]))  # room for the key above the bars
        ax.legend(loc="upper right", frameon=False, fontsize=style.SMALL, handlelength=1.0, borderaxespad=0.2)
        ax.grid(True, axis="y", lw=0.3, alpha=0.6)
    for i in range(n, nrow * ncol):
        axes[i // ncol][i % ncol].axis("off")
    save(fig, root, "episodes", style.TEXT)


def draw_all(root):
    """Every figure of the runs under root, by run setting (runs.SCENES' order), then episodes; False
    (nothing drawn) when there are none. The snapshots and sections need the runs' frames."""
    found = runs.existing_runs(root)
    if not found:
        return False
    scenes = runs.by_setting(found)
    for key, _scene, _title, _force in runs.SCENES:
        if key not in scenes:
            continue
        info = scenes[key]
        # The frames are not committed (results/README.md): where a run has none, its committed
        # snapshot and section figures stay as they are.
        if all(runs.frames_available(p) for p in info["runs"].values()):
            snapshot_figure(root, key, info)
            section_figure(root, key, info)
        else:
            print("figures: %s: no frames (made by scripts/reproduce.sh); snapshots_%s and section_%s kept as "
                  "committed" % (key, key, key))
        timeseries_figure(root, key, info)
    episodes_figure(root, scenes)
    return True
