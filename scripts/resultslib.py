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
ELIM_STYLE = {"line": {"color": "tab:red"}, "plane": {"color": "tab:blue"}}

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
COLUMN = 3.4   # in: one column of the report; figures are drawn at their printed size
PAGE = 7.0     # in: the text width


def pyplot():
    """matplotlib.pyplot with the report's style: text of 7 pt or more at the printed size,
    colour-blind-safe colours, vector PDF beside each PNG (save())."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({
        "font.size": 7, "axes.titlesize": 7.5, "axes.labelsize": 7, "xtick.labelsize": 7, "ytick.labelsize": 7,
        "legend.fontsize": 7, "figure.titlesize": 8, "lines.linewidth": 1.0, "axes.linewidth": 0.6,
        "pdf.fonttype": 42, "savefig.bbox": "tight", "savefig.pad_inches": 0.02,
        "axes.prop_cycle": matplotlib.cycler(color=["#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00",
                                                    "#56B4E9", "#F0E442", "#000000"]),
    })
    return plt


def save(fig, base):
    """base.png (300 dpi) and base.pdf (vector)."""
    import matplotlib.pyplot as plt
    fig.savefig(base + ".png", dpi=300)
    fig.savefig(base + ".pdf")
    plt.close(fig)


def heatmap(ax, m, xlabels, ylabels, title, crossed=()):
    """A matrix as a heat map with its values written in a colour that contrasts with the cell
    (viridis: white on the dark end, black on the bright end); `crossed` cells (x, y) get an X."""
    import numpy as np
    a = np.array(m, dtype=float)
    im = ax.imshow(a, origin="lower", aspect="auto", cmap="viridis")
    finite = a[np.isfinite(a)]
    lo, hi = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            if not np.isfinite(a[i, j]):
                continue
            level = (a[i, j] - lo) / (hi - lo) if hi > lo else 0.0
            ax.text(j, i, "%.2g" % a[i, j], ha="center", va="center", fontsize=6,
                    color="black" if level > 0.55 else "white")
    for j, i in crossed:
        ax.plot([j - 0.45, j + 0.45], [i - 0.45, i + 0.45], color="#D55E00", lw=0.8)
        ax.plot([j - 0.45, j + 0.45], [i + 0.45, i - 0.45], color="#D55E00", lw=0.8)
    ax.set_xticks(range(len(xlabels)))
    ax.set_xticklabels(xlabels, rotation=45, ha="right")
    ax.set_yticks(range(len(ylabels)))
    ax.set_yticklabels(ylabels)
    ax.set_title(title)
    ax.figure.colorbar(im, ax=ax, fraction=0.05, pad=0.02)


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
