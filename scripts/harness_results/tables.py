"""The run tables (scripts/tables.py is the command line), from results/runs/* (steps.csv,
summary.json, frames), written as RESULTS_DIR/tables/<name>.{md,tex,csv} (writers.write_table):

  accuracy      per scenario and eliminator: truly penetrating nodes (guest + host) at the end and
                at the peak (steps.csv, CGAL), deepest node at the end and its peak, the window's
                position error against the reference and its swing, recall, precision, tunnelled
                nodes, stability (the run's C++ class: rules.stability_fields)
  deformation   per body: largest displacement max_i |x_i(end) - x_i(0)| over the surface vertices
                (first and last frames), and largest deformation max_i |d_i - mean(d)| (d_i the
                displacement: the rigid translation removed)
  timing        medians of the per-step wall times (summary.json timing_us), us
  scenes_bodies, scenes_contacts
                the scenarios' parameters, from the resolved scenes of the runs
The first two are identical from one run to the next; timing is measured and varies.
"""

import math
import os

from . import reader, rules, runs, writers
from .reference_kind import of_its_kind


def tex_prose(s):
    """Table text as LaTeX: escaped, with the table's few math expressions typeset."""
    s = writers.tex_escape(s)
    return (s.replace(" x ", " $\\times$ ").replace("beta ", "$\\beta$ ").replace(" > ", " $>$ ")
            .replace(" < ", " $<$ ").replace("-z face", "$-z$ face").replace("-x face", "$-x$ face")
            .replace("+x face", "$+x$ face").replace("-y face", "$-y$ face").replace("+y face", "$+y$ face")
            .replace("+z face", "$+z$ face"))


def write_table(root, name, caption, header, rows, tex_header=None, align=None):
    """root/tables/name.{md,csv,tex} (writers.write_table, the cells' LaTeX by tex_prose). header:
    list of column names (Markdown and CSV); tex_header: LaTeX names (may hold math); rows: lists of
    strings."""
    base = writers.write_table(os.path.join(root, "tables"), name, caption, header, rows, "scripts/tables.py",
                               tex_header=tex_header, align=align, tex_cell=tex_prose)
    print("tables: wrote %s.{md,tex,csv}" % base)


def penetration_stats(cols):
    st, g = reader.measured(cols, "true_pen_guest")
    _, h = reader.measured(cols, "true_pen_host")
    if not st:
        return None, None, None
    tot = [int(a) + int(b) for a, b in zip(g, h)]
    return tot[-1], max(tot), st[tot.index(max(tot))]


def displacement(path, body, steps):
    p0, _t, _ = runs.read_vtk(runs.frame_path(path, body, steps[0]))
    p1, _t, _ = runs.read_vtk(runs.frame_path(path, body, steps[-1]))
    d = [[b[k] - a[k] for k in range(3)] for a, b in zip(p0, p1)]
    n = len(d)
    mean = [sum(v[k] for v in d) / n for k in range(3)]
    disp = max(math.sqrt(sum(v[k] ** 2 for k in range(3))) for v in d)
    defo = max(math.sqrt(sum((v[k] - mean[k]) ** 2 for k in range(3))) for v in d)
    return disp, defo


def collect(root):
    out = []
    for key, scene, title, force, elim, path in runs.existing_runs(root):
        s = reader.load_summary(path)
        cols = reader.load_steps(path)
        final, peak, peak_step = penetration_stats(cols)
        host, guest = reader.contact_bodies(s)
        fr = runs.frames_available(path)
        bodies = {}
        for b in (host, guest):
            steps = fr.get(b, [])
            if len(steps) >= 2 and steps[0] == 0 and steps[-1] == int(reader.steps_run(s)):
                bodies[b] = displacement(path, b, [steps[0], steps[-1]])
            else:
                bodies[b] = (None, None)
        out.append({
            "key": key, "scene": scene, "title": title, "force": force, "elim": elim, "path": path,
            "summary": s, "host": host, "guest": guest, "steps": int(reader.steps_run(s)),
            "voxel": reader.voxel_size_used(s), "pen_final": final, "pen_peak": peak,
            "pen_peak_step": peak_step, "bodies": bodies, "timing": reader.timings(s),
            "status": reader.status(s),
        })
    return out


def mm(v):
    return writers.fmt(None if v is None else v * 1000.0, ".3f")


def _g(v):
    return "%g" % (v * 1000.0)


def shape_text(sh):
    t = sh["type"]
    if t == "box":
        ext = [sh["max"][k] - sh["min"][k] for k in range(3)]
        return "box %s mm, %s cells" % (" x ".join(_g(e) for e in ext), " x ".join(str(c) for c in sh["cells"]))
    if t == "sphere":
        return "icosphere r %s mm, %d subdiv." % (_g(sh["radius"]), sh["subdivisions"])
    if t == "ellipsoid":
        return "ellipsoid %s mm, %d subdiv." % (" x ".join(_g(r) for r in sh["radii"]), sh["subdivisions"])
    if t == "cylinder":
        return "cylinder r %s mm, length %s mm, %d x %d" % (_g(sh["radius"]), _g(sh["length"]), sh["segments"],
                                                            sh["rings"])
    return t


def selection_text(sel):
    if "side" in sel:
        return "%s face" % sel["side"]
    if "all" in sel:
        return "all nodes"
    if "box" in sel:
        parts = []
        for k, a in enumerate("xyz"):
            lo, hi = sel["box"]["min"][k], sel["box"]["max"][k]
            if lo > -1.0:
                parts.append("%s > %s mm" % (a, _g(lo)))
            if hi < 1.0:
                parts.append("%s < %s mm" % (a, _g(hi)))
        return ", ".join(parts) if parts else "box"
    return "?"


def constraints_text(b, effects):
    out = []
    if b.get("pins") and "pins" in effects:
        out.append("pinned: " + "; ".join(selection_text(x) for x in b["pins"]))
    if b.get("drivers") and "drivers" in effects:
        for d in b["drivers"]:
            out.append("driven %s at (%s) m/s, steps %d-%d" % (selection_text(d["select"]),
                                                               ", ".join("%g" % v for v in d["velocity"]),
                                                               d["from_step"], d["to_step"]))
    if b.get("pressure") and "pressure" in effects:
        pr = b["pressure"]
        out.append("pressure %g to %g Pa over %d steps" % (pr["from"], pr["to"], pr["ramp_steps"]))
    if any(v != 0.0 for v in b.get("velocity", [0, 0, 0])):
        out.append("initial velocity (%s) m/s" % ", ".join("%g" % v for v in b["velocity"]))
    return "; ".join(out) if out else "free"


def stiffness_text(m):
    """E in kPa (and the shell's thickness) when the material gives Young's modulus, else k in N/m."""
    if "youngs_modulus" in m:
        t = " t %g mm" % (1e3 * m["thickness"]) if "thickness" in m else ""
        return "E %g kPa%s" % (m["youngs_modulus"] / 1e3, t)
    return "k %g N/m" % m["stiffness"]


def body_rows(r):
    """scenes_bodies' rows of one run's scene: a row per body of its resolved scene."""
    s = r["summary"]
    host, guest = reader.contact_bodies(s)
    rows = []
    for b in reader.scene_bodies(s):
        m = b["material"]
        role = "host" if b["name"] == host else ("guest" if b["name"] == guest else "")
        law = m["law"] + ("" if m["law"] == "linear" else " (beta %g)" % m["nonlinearity"])
        rows.append([r["title"].split(",")[0], "%s (%s)" % (b["name"], role), shape_text(b["shape"]),
                     b["shape"].get("fill", "volume"), "%g" % m["density"], stiffness_text(m), law,
                     "%g" % m["damping"], constraints_text(b, reader.scene_effects(s))])
    return rows


def object_force(f):
    """An object force: the penalty's k in N/m, another rule by its name and parameters."""
    if set(f) == {"stiffness"}:
        return "k %g N/m" % f["stiffness"]
    return "%s %s" % (f.get("rule", "penalty"), " ".join("%s %g" % (k, v) for k, v in f.items() if k != "rule"))


def contact_row(r):
    """scenes_contacts' row of one run: its time stepping and contact pair."""
    s = r["summary"]
    c = reader.contact(s)
    f = c["force"]
    force = "auto" if f == "auto" else (object_force(f) if isinstance(f, dict) else "%g N" % f)
    return [r["title"], "%g" % (reader.scene_dt(s) * 1e6), "%d" % r["steps"], ", ".join(reader.scene_effects(s)),
            c["host"], c["guest"],
            c["voxel_size"] if isinstance(c["voxel_size"], str) else "%g" % (c["voxel_size"] * 1000.0),
            "%.4g" % (r["voxel"] * 1000.0),
            c["region"], "%d" % c["margin"], force,
            "%d" % reader.measure_every(s)]


def scene_tables(root, data):
    rows = []
    crow = []
    seen = set()
    for r in data:
        if r["scene"] not in seen:
            seen.add(r["scene"])
            rows += body_rows(r)
        if r["elim"] == runs.ELIMINATORS[0]:
            crow.append(contact_row(r))
    write_table(
        root, "scenes_bodies",
        "Bodies of the bundled scenes (experiments/scenes/*.json, resolved): shape, fill, density "
        "(kg/m^3), Young's modulus E (or spring stiffness k), spring law, dashpot damping (N s/m), constraints.",
        ["scenario", "body", "shape", "fill", "density", "stiffness", "law", "damping", "constraints"],
        rows, tex_header=["scenario", "body", "shape", "fill", "$\\rho$", "$E$ or $k$", "law", "$c$", "constraints"],
        align="llp{3.2cm}lrrlrp{4.2cm}")
    write_table(
        root, "scenes_contacts",
        "Time stepping and contact pair of each scenario (both eliminators are run on each).",
        ["scenario", "dt (us)", "steps", "effects", "host", "guest", "voxel asked (mm)", "voxel used (mm)",
         "region", "margin", "force", "measured every"],
        crow, tex_header=["scenario", "$\\Delta t$ ($\\mu$s)", "steps", "effects", "host", "guest",
                          "$v$ asked", "$v$ used", "region", "margin", "force", "every"],
        align="lrrp{3cm}llrrlrll")


def useless_of(r, bases):
    """The useless words (rules.useless_text) of one run: its window figures against the reference of
    its kind, against its scene's run without contact force on the same kind."""
    k, kind = of_its_kind(r["summary"])
    f = dict(reader.window_figures(k), scene=r["scene"], reference=kind)
    return rules.mark_useless([f], bases)[0]["useless"]


def accuracy_row(r, bases):
    """accuracy's row of one run: its position error against the reference of its kind, the other
    kind's beside."""
    s = r["summary"]
    k, kind = of_its_kind(s)
    return [r["title"], r["elim"], r["force"], "%.4g" % (r["voxel"] * 1000.0), "%d" % r["steps"],
            writers.fmt(r["pen_final"], "d"), writers.fmt(r["pen_peak"], "d"),
            mm(reader.pair_value(s, "max_depth_final")), mm(reader.pair_value(s, "max_depth_peak")),
            mm(reader.pair_window_stat(k, "pos_err_max", "mean")),
            mm(reader.pair_window_stat(k, "pos_err_max", "amplitude")),
            {"one-sided": "one way", "both ways": "both ways"}[kind],
            mm(reader.pair_window_stat(s, "pos_err_max", "mean")) if k is not s else "-",
            writers.fmt(reader.pair_value(s, "recall"), ".3f"), writers.fmt(reader.pair_value(s, "precision"), ".4f"),
            writers.fmt(reader.tunnelled_peak(s), "d"),
            rules.stability_fields(s)["stability"], useless_of(r, bases)]


# accuracy.tex's header spans two columns per pair of figures: the line below it names them.
ACCURACY_SUBHEADER = " & & & & & final & peak & final & peak & window & swing & & (mm) & & & & & \\\\\n"


def accuracy_table(root, data):
    bases = rules.no_force_bases(root)
    write_table(
        root, "accuracy",
        "Accuracy per scenario and eliminator. Truly penetrating nodes: guest + host nodes strictly "
        "inside the other body (CGAL), at the last step and the peak over the measured steps. "
        "Depth: deepest node inside the other body (mm), at the last step and its peak over the run. "
        "Position error against the reference of the run's kind (the paper's model is one-sided: against the "
        "one-way reference where the scene has one, measured beside the both-ways one): window mean and swing "
        "(max - min over the window), mm; the reference it is against, and the error against the both-ways "
        "reference beside. "
        "Tunnelled: peak of the nodes that passed through. Stability: the studies' rule (rules.py); "
        "useless, whatever the stability: tunnels (over the window) or no better than no force.",
        ["scenario", "eliminator", "force", "voxel (mm)", "steps", "pen. final", "pen. peak",
         "depth final (mm)", "depth peak (mm)", "pos. error (mm)", "error swing (mm)", "reference",
         "pos. error both ways (mm)", "recall", "precision", "tunnelled", "stability", "useless"],
        [accuracy_row(r, bases) for r in data],
        tex_header=["scenario", "elim.", "force", "$v$ (mm)", "steps", "\\multicolumn{2}{c}{penetrating}",
                    "\\multicolumn{2}{c}{depth (mm)}", "\\multicolumn{2}{c}{pos. error (mm)}", "ref.", "both ways",
                    "recall", "prec.", "tunn.", "stability", "useless"],
        align="lllrrrrrrrrlrrrrll")
    texp = os.path.join(root, "tables", "accuracy.tex")
    with open(texp) as f:
        t = f.read()
    writers.write_text(texp, t.replace("\\\\\n\\midrule\n", "\\\\\n" + ACCURACY_SUBHEADER + "\\midrule\n", 1))


def deformation_table(root, data):
    rows = []
    for r in data:
        h = r["bodies"][r["host"]]
        g = r["bodies"][r["guest"]]
        rows.append([r["title"], r["elim"], r["host"], mm(h[0]), mm(h[1]), r["guest"], mm(g[0]), mm(g[1])])
    write_table(
        root, "deformation",
        "Largest displacement max_i |x_i(end) - x_i(0)| and largest deformation max_i |d_i - mean d| "
        "(displacement minus the body's mean displacement) over the surface vertices, mm.",
        ["scenario", "eliminator", "host", "host displacement (mm)", "host deformation (mm)",
         "guest", "guest displacement (mm)", "guest deformation (mm)"],
        rows,
        tex_header=["scenario", "elim.", "host", "displ. (mm)", "deform. (mm)", "guest", "displ. (mm)",
                    "deform. (mm)"],
        align="lllrrlrr")


def timing_table(root, data):
    rows = []
    for r in data:
        t = r["timing"]
        rows.append([r["title"], r["elim"], writers.fmt(t.get("step"), ".1f"), writers.fmt(t.get("physics"), ".1f"),
                     writers.fmt(t.get("detect"), ".1f"), writers.fmt(t.get("eliminate"), ".1f"),
                     writers.fmt(t.get("fcl"), ".1f"), writers.fmt(t.get("cgal"), ".1f")])
    write_table(
        root, "timing",
        "Median wall time per step, microseconds (one core). Detection and elimination are the voxel "
        "model's; FCL and CGAL are the references, on measured steps only (not part of the step).",
        ["scenario", "eliminator", "step (us)", "physics (us)", "detection (us)", "elimination (us)",
         "FCL (us)", "CGAL (us)"],
        rows,
        tex_header=["scenario", "elim.", "step", "physics", "detection", "elimination", "FCL", "CGAL"])


def write_all(root):
    """Every table of the runs under root (accuracy, deformation, timing, scenes_bodies,
    scenes_contacts); False (nothing written) when there are none."""
    data = collect(root)
    if not data:
        return False
    accuracy_table(root, data)
    deformation_table(root, data)
    timing_table(root, data)
    scene_tables(root, data)
    return True
