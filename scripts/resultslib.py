"""Shared helpers of the result scripts (figures.py, tables.py, claims.py, study.py, prune_frames.py).

Reads the outputs of `harness run` (steps.csv, summary.json, penetration_episodes.csv,
frames/*.vtk) under results/runs/<run>/. Everything here is deterministic: fixed run order,
sorted file lists, no dates.
"""

import csv
import json
import math
import os
import re

# The runs that scripts/reproduce.sh makes, in the order tables and figures show them:
# (run folder, scene, eliminator, label of the force setting).
SCENES = [
    # (key, bundled scene, title, force label)
    ("sphere_collision", "sphere_collision", "Sphere collision", "auto"),
    ("cylinder_press", "cylinder_press", "Cylinder press", "auto"),
    ("cylinder_press_f003", "cylinder_press", "Cylinder press, F = 0.03 N, 8 mm voxels", "0.03 N"),
    ("implant_expansion", "implant_expansion", "Implant expansion", "auto"),
    ("implant_expansion_f002", "implant_expansion", "Implant expansion, F = 0.02 N", "0.02 N"),
]
ELIMINATORS = ["line", "plane"]
ELIM_STYLE = {"line": {"color": "#D55E00"}, "plane": {"color": "#0072B2"}}  # Okabe-Ito vermilion, blue

# Instants of the snapshot figures, as fractions of the run (rounded to the nearest frame).
SNAPSHOT_FRACTIONS = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]


def run_name(scene_key, elim):
    return "%s_%s" % (scene_key, elim)


def runs_dir(root):
    return os.path.join(root, "runs")


def existing_runs(root):
    """[(scene_key, scene, title, force_label, elim, path)] for the runs present, in order."""
    out = []
    for key, scene, title, force in SCENES:
        for e in ELIMINATORS:
            p = os.path.join(runs_dir(root), run_name(key, e))
            if os.path.isfile(os.path.join(p, "summary.json")):
                out.append((key, scene, title, force, e, p))
    return out


def load_summary(path):
    with open(os.path.join(path, "summary.json")) as f:
        return json.load(f)


def _num(s):
    if s is None or s == "":
        return None
    return float(s)


def load_steps(path):
    """steps.csv of a single-pair run as a dict of column -> list (floats, None when empty)."""
    with open(os.path.join(path, "steps.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for k in rows[0].keys() if rows else []:
        if k in ("pair", "detector"):
            cols[k] = [r[k] for r in rows]
        else:
            cols[k] = [_num(r[k]) for r in rows]
    return cols


def measured(cols, key):
    """(steps, values) of the rows where column `key` was measured."""
    st, va = [], []
    for s, v in zip(cols["step"], cols[key]):
        if v is not None:
            st.append(int(s))
            va.append(v)
    return st, va


def load_episodes(path):
    p = os.path.join(path, "penetration_episodes.csv")
    if not os.path.isfile(p):
        return []
    with open(p, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("node", "first_step", "last_step", "steps", "open"):
            r[k] = int(r[k])
    return rows


def frames_available(path):
    """{body: sorted list of steps} of the frames present."""
    d = os.path.join(path, "frames")
    out = {}
    if not os.path.isdir(d):
        return out
    for name in sorted(os.listdir(d)):
        m = re.match(r"^(.+)_(\d{6})\.vtk$", name)
        if m:
            out.setdefault(m.group(1), []).append(int(m.group(2)))
    return out


def frame_path(path, body, step):
    return os.path.join(path, "frames", "%s_%06d.vtk" % (body, step))


def snapshot_steps(summary):
    """Steps shown in the snapshot figures: SNAPSHOT_FRACTIONS of the run, rounded to the
    nearest multiple of output.frames_every (the last one is the final step)."""
    n = int(summary["steps_run"])
    fe = int(summary["resolved_scene"].get("output", {}).get("frames_every", 0) or 0)
    steps = []
    for f in SNAPSHOT_FRACTIONS:
        if f >= 1.0 or fe <= 0:
            s = n if f >= 1.0 else 0
        else:
            s = int(math.floor(f * n / fe + 0.5)) * fe
            s = min(s, n)
        if s not in steps:
            steps.append(s)
    return steps


def body_names(summary):
    """(host, guest) names of the first contact pair."""
    sc = summary["resolved_scene"]
    c = sc["contacts"][0]
    return c["host"], c["guest"]


def read_vtk(fname):
    """Legacy ASCII VTK POLYDATA -> (points Nx3 list, triangles Mx3 list, penetrating list or None)."""
    with open(fname) as f:
        tok = f.read().split("\n")
    i = 0
    pts, tris, pen = [], [], None
    while i < len(tok):
        line = tok[i].strip()
        if line.startswith("POINTS"):
            n = int(line.split()[1])
            vals = []
            i += 1
            while len(vals) < 3 * n:
                vals.extend(float(x) for x in tok[i].split())
                i += 1
            pts = [vals[3 * k:3 * k + 3] for k in range(n)]
            continue
        if line.startswith("POLYGONS"):
            n = int(line.split()[1])
            for k in range(n):
                a = tok[i + 1 + k].split()
                tris.append([int(a[1]), int(a[2]), int(a[3])])
            i += n + 1
            continue
        if line.startswith("SCALARS penetrating"):
            i += 1
            if tok[i].strip().startswith("LOOKUP_TABLE"):
                i += 1
            vals = []
            while len(vals) < len(pts) and i < len(tok):
                vals.extend(int(x) for x in tok[i].split())
                i += 1
            pen = vals[:len(pts)]
            continue
        i += 1
    return pts, tris, pen


def steps_row(cols, step):
    """Index of the row of `step` (the first row for step 0, which has none)."""
    st = cols["step"]
    target = max(1, step)
    for k, s in enumerate(st):
        if int(s) >= target:
            return k
    return len(st) - 1


def region_at(cols, step):
    k = steps_row(cols, step)
    lo = [cols["region_lo_%s" % a][k] for a in "xyz"]
    hi = [cols["region_hi_%s" % a][k] for a in "xyz"]
    if any(v is None for v in lo + hi):
        return None
    return lo, hi


def nearest_rank(sorted_vals, q):
    """Nearest-rank percentile q in (0, 100] of an ascending list (an observed value)."""
    if not sorted_vals:
        return None
    k = max(1, int(math.ceil(q / 100.0 * len(sorted_vals))))
    return sorted_vals[k - 1]


def tex_escape(v):
    """A value as LaTeX text: the characters LaTeX treats specially are escaped."""
    return (str(v).replace("\\", "\\textbackslash{}").replace("_", "\\_").replace("%", "\\%")
            .replace("&", "\\&").replace("#", "\\#"))


def fmt(v, spec):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "n/a"
    return format(v, spec)


# ---------------------------------------------------------------------------------------------
# Tables and figures shared by the scripts.
#
# Every figure is drawn at the width the report prints it at, so that nothing is scaled and the
# text is printed at the size set here (8 pt; 7 pt for the numbers in heat-map cells and for
# dense keys). paper/main.tex (article, 11pt, a4paper, geometry margin=2.2cm) has
# \textwidth = 472.316 pt (measured with \the\textwidth); a figure is included with
# width=\linewidth, either in the text (TEXT) or in a minipage{0.49\textwidth} (HALF).
# Change these when the report's page layout changes.
TEXT = 472.31595 / 72.27  # in: 6.535
HALF = 0.49 * TEXT        # in: 3.202
FONT = 8.0                # pt: every text of a figure
SMALL = 7.0               # pt: numbers in heat-map cells, keys of many entries (the least)
PALETTE = ["#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00", "#56B4E9", "#F0E442", "#000000"]  # Okabe-Ito


def pyplot():
    """matplotlib.pyplot with the report's style (one style for every script): text of FONT pt
    (never below SMALL) at the printed size, colour-blind-safe colours, TrueType (type 42) fonts
    in the PDF. Make figures with figsize=(TEXT or HALF, height) and layout="constrained" and
    write them with save(): the files keep exactly that size."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({
        "font.size": FONT, "axes.titlesize": FONT, "axes.labelsize": FONT, "xtick.labelsize": FONT,
        "ytick.labelsize": FONT, "legend.fontsize": FONT, "legend.title_fontsize": FONT, "figure.titlesize": FONT,
        "lines.linewidth": 1.0, "lines.markersize": 4, "axes.linewidth": 0.6, "grid.linewidth": 0.4,
        "xtick.major.width": 0.6, "ytick.major.width": 0.6, "xtick.minor.width": 0.4, "ytick.minor.width": 0.4,
        "xtick.major.size": 3, "ytick.major.size": 3, "xtick.minor.size": 1.8, "ytick.minor.size": 1.8,
        "axes.titlepad": 4, "legend.handlelength": 1.6, "legend.borderaxespad": 0.3,
        "pdf.fonttype": 42, "ps.fonttype": 42, "image.cmap": "viridis",
        "savefig.bbox": None, "figure.dpi": 100, "svg.hashsalt": "harness",
        "figure.constrained_layout.h_pad": 0.02, "figure.constrained_layout.w_pad": 0.02,
        "axes.prop_cycle": matplotlib.cycler(color=PALETTE),
    })
    return plt


def save(fig, base, width=None):
    """base.png (300 dpi) and base.pdf (vector, the one the report includes), both exactly the
    figure's size (no tight bounding box: the size is the printed size). No dates or software
    versions are written, so the files depend only on the data. `width` (in), when given, is
    checked against the figure's width."""
    import matplotlib.pyplot as plt
    w, h = fig.get_size_inches()
    if width is not None and abs(w - width) > 1e-6:
        raise ValueError("%s: figure is %.3f in wide, printed at %.3f in" % (base, w, width))
    os.makedirs(os.path.dirname(base) or ".", exist_ok=True)
    fig.savefig(base + ".png", dpi=300, metadata={"Software": None})
    fig.savefig(base + ".pdf", metadata={"CreationDate": None, "Producer": None, "Creator": None})
    plt.close(fig)
    print("wrote %s.{png,pdf} (%.2f x %.2f in)" % (base, w, h))


def plain_log_ticks(*axes_):
    """Log-axis tick labels as plain numbers (0.1, 10, 1 000, 100 000: thin-space thousands)
    instead of powers of ten, whose superscripts would print below 7 pt."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    def show(v, _pos=None):
        if v >= 1000:
            return format(v, ",.0f").replace(",", "\u2009")
        return "%g" % v
    for axis in axes_:
        axis.set_major_formatter(FuncFormatter(show))
        axis.set_minor_formatter(NullFormatter())


def luminance(rgba):
    """Relative luminance (WCAG) of an sRGB colour."""
    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgba[:3]]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


def text_colour(rgba):
    """Black or white, whichever contrasts more with a background of colour rgba (black when the
    luminance is above 0.179, where the two contrast ratios are equal)."""
    return "black" if luminance(rgba) > 0.179 else "white"


def heatmap(ax, m, xlabels, ylabels, title, outlined=(), cmap="viridis", fmt="%.2g", cap=None, cap_text=None):
    """A matrix as a heat map (perceptually uniform colour map) with its values written in black
    or white according to the luminance of each cell's colour; `outlined` cells (x, y) get a
    frame (black inside white, visible on any colour). Values above `cap` (runs that blew up) do
    not stretch the scale: their cells are vermilion, labelled `cap_text`. Missing values: grey,
    "n/a". Returns the image (for a colour bar)."""
    import copy
    import numpy as np
    from matplotlib import colormaps
    from matplotlib.patches import Rectangle
    a = np.array(m, dtype=float)
    shown = a[np.isfinite(a) & (a <= cap if cap is not None else True)]
    cm = copy.copy(colormaps[cmap])
    cm.set_bad("#dddddd")
    cm.set_over("#D55E00")
    im = ax.imshow(np.ma.masked_invalid(a), origin="lower", aspect="auto", cmap=cm,
                   vmin=shown.min() if shown.size else None, vmax=shown.max() if shown.size else None)
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            v = a[i, j]
            if not np.isfinite(v):
                ax.text(j, i, "n/a", ha="center", va="center", fontsize=SMALL, color="black")
            elif cap is not None and v > cap:
                ax.text(j, i, cap_text or (">" + fmt % cap), ha="center", va="center", fontsize=SMALL,
                        color=text_colour(cm.get_over()))
            else:
                ax.text(j, i, fmt % v, ha="center", va="center", fontsize=SMALL, color=text_colour(cm(im.norm(v))))
    for j, i in outlined:
        ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="white", lw=2.4, zorder=3))
        ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="black", lw=1.0, zorder=4))
    ax.set_xticks(range(len(xlabels)))
    ax.set_xticklabels(xlabels, rotation=45, ha="right", rotation_mode="anchor")
    ax.set_yticks(range(len(ylabels)))
    ax.set_yticklabels(ylabels)
    ax.tick_params(length=0)
    ax.set_title(title)
    return im


def place_labels(ax, points, labels, avoid=(), lines=(), fontsize=SMALL, radius=5.0):
    """Writes labels[k] next to points[k] (data coordinates) where it overlaps neither a label
    already placed, nor a marker (points and `avoid`), nor a line (`lines`: polylines in data
    coordinates), nor the axes' edge. Candidates: 8 directions at growing distances; the free one
    of least cost wins (farther costs more, and so does a place nearer to another labelled point
    than to its own, which would read as that point's label); a thin leader line when it is not
    the nearest ring. Call it after the axes' limits and scales are final."""
    import numpy as np
    fig = ax.figure
    fig.canvas.draw()
    px = fig.dpi / 72.0
    tr = ax.transData
    box = ax.get_window_extent()
    own = [tr.transform(p) for p in points]
    marks = own + [tr.transform(p) for p in avoid]
    mr = 3.5 * px  # half size of a marker, pixels
    taken = [(x - mr, y - mr, x + mr, y + mr) for x, y in marks]
    lw = 1.0 * px
    for line in lines:
        d = [tr.transform(p) for p in line]
        for (x0, y0), (x1, y1) in zip(d[:-1], d[1:]):
            n = max(1, int(math.hypot(x1 - x0, y1 - y0) / (2 * px)))
            for k in range(n + 1):
                x, y = x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n
                taken.append((x - lw, y - lw, x + lw, y + lw))
    dirs = [(0, -1), (-1, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (1, 1), (0, 1)]
    rings = (1.0, 1.8, 2.8, 4.0, 5.5, 7.5)
    for k, ((x, y), text) in enumerate(zip(own, labels)):
        w = (0.62 * fontsize * len(text) + 2) * px
        h = (fontsize + 1) * px
        best = None
        for ri, ring in enumerate(rings):
            for di, (dx, dy) in enumerate(dirs):
                n = math.hypot(dx, dy)
                cx = x + dx / n * radius * ring * px + dx * w / 2
                cy = y + dy / n * radius * ring * px + dy * h / 2
                b = (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2)
                if not (b[0] >= box.x0 and b[2] <= box.x1 and b[1] >= box.y0 and b[3] <= box.y1):
                    continue
                if any(b[0] < t[2] and t[0] < b[2] and b[1] < t[3] and t[1] < b[3] for t in taken):
                    continue
                mine = math.hypot(cx - x, cy - y)
                misread = any(math.hypot(cx - ox, cy - oy) < mine for j, (ox, oy) in enumerate(own) if j != k)
                cost = 3.0 * ri + 0.1 * di + (10.0 if misread else 0.0)
                if best is None or cost < best[0]:
                    best = (cost, cx, cy, b, ring)
        if best is None:  # no free place: the nearest one
            cx, cy = x + radius * px + w / 2, y + radius * px + h / 2
            best = (0.0, cx, cy, (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2), 1.0)
        _, cx, cy, b, ring = best
        taken.append(b)
        ann = ax.annotate(text, xy=tuple(np.asarray(tr.inverted().transform((x, y)))),
                          xytext=((cx - x) / px, (cy - y) / px), textcoords="offset points", ha="center",
                          va="center", fontsize=fontsize, zorder=6,
                          arrowprops=(dict(arrowstyle="-", lw=0.4, color="0.3", shrinkA=0, shrinkB=2.5)
                                      if ring > 1.0 else None))
        ann.set_in_layout(False)


def median(v):
    s = sorted(x for x in v if not (isinstance(x, float) and math.isnan(x)))
    if not s:
        return float("nan")
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def cell(v):
    if isinstance(v, float):
        return "" if math.isnan(v) else "%.6g" % v
    return v


def write_csv(path, rows, cols):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(cols)
        for r in rows:
            w.writerow([cell(r.get(c, "")) for c in cols])


def md_table(rows, cols, heads):
    def show(v):
        if isinstance(v, float):
            return "" if math.isnan(v) else "%.4g" % v
        return str(v)
    out = ["| " + " | ".join(heads) + " |", "|" + "---|" * len(heads)]
    for r in rows:
        out.append("| " + " | ".join(show(r.get(c, "")) for c in cols) + " |")
    return "\n".join(out) + "\n"


def tex_table(rows, cols, heads, caption):
    def show(v):
        if isinstance(v, float):
            return "--" if math.isnan(v) else "%.3g" % v
        return tex_escape(v)
    out = ["\\begin{tabular}{" + "l" * 2 + "r" * (len(cols) - 2) + "}", "\\toprule", " & ".join(heads) + " \\\\",
           "\\midrule"]
    for r in rows:
        out.append(" & ".join(show(r.get(c, "")) for c in cols) + " \\\\")
    out += ["\\bottomrule", "\\end{tabular}"]
    return "% " + caption + " (made by scripts/study.py)\n" + "\n".join(out) + "\n"


def bundled_scene(scene):
    """experiments/scenes/<scene>.json, parsed."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "experiments", "scenes", scene + ".json")
    with open(path) as f:
        return json.load(f)


def load_surfaces(path):
    """surfaces.csv of a run: {body: [(x, y, z, x0, y0, z0, signed distance or None)]}."""
    out = {}
    with open(os.path.join(path, "surfaces.csv"), newline="") as f:
        for r in csv.DictReader(f):
            out.setdefault(r["body"], []).append(tuple(float(r[k]) for k in ("x", "y", "z", "x0", "y0", "z0")) +
                                                 (float(r["signed_distance"]) if r["signed_distance"] else None,))
    return out


def largest_displacements(path):
    """{body: largest distance of a surface vertex from its rest position (m)} after the run."""
    return {b: max(math.dist(v[:3], v[3:6]) for v in vs) for b, vs in load_surfaces(path).items()}
