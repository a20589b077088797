"""study.py accuracy: what accuracy costs in time.

The voxel model (voxels at and above the host's node spacing; line, plane, projection; constant
forces 0.0005-0.01 N, `auto`, penalty), the completed voxel model (voxel_exact), spatial hashing,
CGAL and FCL on the three scenes (FOOTING_VOXELS below), error against the reference over the
final window, stability, µs per step (median of --repeats runs: the first measured, the others
timing only) -> accuracy_time.csv, figures/pareto_<scene>.{png,pdf}, tables/accuracy_time.md,
tables/accuracy_time_front.tex; the Pareto front (rules.pareto) of the evidence.
"""

import math
import os

from .. import methods, reader, rules, runner, style, writers
from ..style import DETECTOR_COLOUR, ELIMINATOR_MARKER
from .common import (PARETO_CAP_MM, PENALTY, STUDY_EVERY, columns_of, combine, committed_timings, config_sets,
                     figure_path, figures,
                     folder_name, footing_voxels, force_label, is_user_row, kind_floor_mm, notes, read_rows,
                     reference_of_kind, resolved_force_label, scenes, table_path, user_fields, user_method_sets,
                     user_methods, user_two_sided, with_both_kinds)

# The equal-footing comparison: the paper's voxel model with voxels at or above the host's node
# spacing (host mean surface edge: sphere 3.0 mm, layer 5.7 mm, implant 6.1 mm; the smallest power
# of two above it and twice it: below it a host voxel can hold no node while a guest node sits
# inside the host), forces from 0.0005 to 0.01 N and `auto`, line and plane, penalty and
# projection; the completed model (voxel_exact) with its voxel swept one size further; spatial
# hashing, CGAL and FCL with the same responses; both ways where the detector offers it.
FOOTING_VOXELS = {"sphere_collision": [0.004, 0.008], "cylinder_press": [0.008, 0.016],
                  "implant_expansion": [0.008, 0.016]}
FOOTING_FORCES = ["0.0005", "0.001", "0.003", "0.01", "auto"]
BOTH_WAYS = ["contacts.0.two_sided=true"]
BOUND = "references.volume=true"
NO_FORCE = rules.NO_FORCE
TWIN_KEYS = ("scene", "config", "detector", "eliminator", "force", "two_sided", "reference")  # a row's identity
USELESS_FILL = "0.8"  # the fill of a stable run that tunnels or is no better than no force


def method_configs(a, scene):
    """(label, detector, voxel size or None, eliminator, force, extra sets) of the comparison."""
    out = []
    voxels = footing_voxels(a, scene, FOOTING_VOXELS)
    for v in voxels:
        label = "voxel %g mm" % (1e3 * v)
        for e in ["line", "plane"]:
            for f in FOOTING_FORCES:
                out.append((label, "voxel", v, e, f, []))
        out.append((label, "voxel", v, "line", PENALTY, []))
        out.append((label, "voxel", v, "projection", "auto", [BOUND]))
    for v in voxels + [2 * voxels[-1]]:
        label = "voxel_exact %g mm" % (1e3 * v)
        out.append((label, "voxel_exact", v, "line", "auto", []))
        out.append((label, "voxel_exact", v, "line", PENALTY, []))
        out.append((label + ", both ways", "voxel_exact", v, "line", PENALTY, BOTH_WAYS))
    for d in ["hash", "cgal", "fcl"]:
        for f in ["auto", PENALTY]:
            out.append((d, d, None, "line", f, []))
        # The restriction (positions projected out): its run also times the penetration region's
        # bound (CGAL's corefinement of the two surfaces, references.volume) for claim (c).
        out.append((d, d, None, "projection", "auto", [BOUND]))
    for d in ["hash", "cgal"]:
        out.append((d + ", both ways", d, None, "line", PENALTY, BOTH_WAYS))
    # The baseline: contact detected, never pushed (the run a useful setting must beat).
    out.append((NO_FORCE, "voxel", voxels[0], "line", "0", []))
    return out


def bound_time_us(folder):
    """Median µs of CGAL's corefinement of the two surfaces (the penetration region's bound) over the
    run's measured steps that computed it (steps.csv t_volume_us); NaN when none did."""
    try:
        _, v = reader.measured(reader.load_steps(folder), "t_volume_us")
    except (OSError, KeyError):
        return float("nan")
    return rules.median(v)


def run(a):
    rows, jobs, index = [], [], []
    for scene in scenes(a):
        for label, det, voxel, elim, force, extra in method_configs(a, scene):
            kind, ref, other = reference_of_kind(a, scene, BOTH_WAYS[0] in extra)
            js = runner.repeated(a, scene, "accuracy/" + folder_name(scene, label, elim, force),
                                 config_sets(det, voxel, elim, force, extra), compare=(ref, other))
            index.append((scene, (label, det, voxel, elim, force, extra), None, kind, len(jobs), len(js)))
            jobs += js
        for m in user_methods(a):  # study.py --method: the scene as written with the method's overrides
            kind, ref, other = reference_of_kind(a, scene, user_two_sided(a, scene, m))
            js = runner.repeated(a, scene, "accuracy/%s/%s" % (scene, methods.folder(m)), user_method_sets(m),
                                 compare=(ref, other))
            index.append((scene, None, m, kind, len(jobs), len(js)))
            jobs += js
    sums = runner.run_all(a, jobs)
    for scene, config, m, kind, i, n in index:
        row = dict(combine(sums[i:i + n]), scene=scene, reference=kind)
        if m is None:
            label, det, voxel, elim, force, extra = config
            row.update(config=label, detector=det, eliminator=elim,
                       force=force_label(force) if elim != "projection" else "positions",
                       voxel_mm=1e3 * voxel if voxel else float("nan"),
                       two_sided="yes" if BOTH_WAYS[0] in extra else "no",
                       t_bound_us=bound_time_us(jobs[i][1]) if BOUND in extra else float("nan"))
            if user_methods(a):
                row.update(method="", overrides="")
        else:
            row.update(user_row(a, scene, m, sums[i]),
                       t_bound_us=bound_time_us(jobs[i][1]) if methods.value(m.sets, "references.volume")
                       else float("nan"))
        with_both_kinds(row, sums[i], kind)  # the other kind, measured on the same steps
        row["one_sided_cost_mm"] = one_sided_cost_mm(a, scene)
        rows.append(row)
    write(a, committed_timings(a, "accuracy_time.csv", rows, TWIN_KEYS))


def user_row(a, scene, m, s):
    """The columns that name a user's method's row: config (its name), detector, eliminator, force
    and voxel as its run resolved them (its summary), both ways or not, method and overrides."""
    c = reader.contact(s, strict=False)
    elim = c.get("eliminator", "")
    v = reader.num(reader.window_figures(s).get("voxel_size_used")) if c else float("nan")
    return dict(user_fields(m), config=m.name, detector=c.get("detector", ""), eliminator=elim,
                force="positions" if elim == "projection" else resolved_force_label(c),
                voxel_mm=1e3 * v if c.get("detector", "").startswith("voxel") else float("nan"),
                two_sided="yes" if user_two_sided(a, scene, m) else "no")


COLUMNS = ["scene", "config", "detector", "eliminator", "force", "stable", "why_unstable", "settled", "steps",
           "pos_err_max_mm", "pos_err_max_max_mm", "pos_err_amp_mm", "pos_err_final_mm", "pos_err_rms_mm", "gap_max_mm",
           "gap_mean_mm", "depth_max_mm", "depth_peak_mm", "tunnelled", "tunnelled_peak", "stability", "verdict",
           "contact_power_ratio", "recall", "precision", "recall_host", "precision_host", "beyond_band_total",
           "t_contact_us", "t_contact_range", "t_contact_min_us", "t_contact_max_us", "t_step_us", "t_step_min_us",
           "t_step_max_us", "t_bound_us", "voxel_mm", "two_sided", "repeats", "helps", "useless", "front",
           "t_step_mean_us", "t_step_p99_us", "t_contact_mean_us", "t_contact_p99_us", "machine", "reference",
           "pos_err_max_one_sided_mm", "pos_err_max_both_ways_mm", "one_sided_cost_mm", "rho_norm"]


def one_sided_cost_mm(a, scene):
    """The largest distance between the scene's one-sided and two-sided references (mm; what
    one-sidedness alone costs a one-sided method), from references_differences.csv; NaN without it."""
    for r in reader.read_csv(os.path.join(a.results, "references_differences.csv"), missing=[]):
        if str(r.get("comparison", "")).startswith(scene + ": one way against both ways"):
            return reader.num(r.get("difference_mm"))
    return float("nan")


def write(a, rows):
    """accuracy_time.csv, tables/accuracy_time.md, tables/accuracy_time_front.tex and the Pareto
    figures from the study's rows: each row marked helps / useless against its scene's run without
    contact force (rules.mark_useless) and on the front or not (rules.pareto over the evidence, with
    the scene's reference floor in the noise)."""
    bases = {r["scene"]: r for r in rows if r["config"] == NO_FORCE}
    rules.mark_useless(rows, bases)
    for r in rows:
        r["front"] = ""
    repeats = int(max(reader.num(r.get("repeats"), a.repeats) for r in rows)) if rows else a.repeats
    protocol = any(reader.present(r.get("t_step_mean_us")) for r in rows)
    md = ["# What accuracy costs in time\n\n",
          "Every method on every scenario, judged by its error against the scenario's reference solution of "
          "the method's kind (`reference`: a one-sided method against `references/<scene>_one_sided`, the limit it "
          "converges to; a method both ways against `references/<scene>`; the position error against both beside "
          "it, and one_sided_cost, the two references apart: what one-sidedness alone costs) over the run's final window (`time.window` steps after every driver and "
          "load has finished; CGAL every %d steps): pos_err_max: largest distance of a surface vertex from "
          "the reference, window mean (max and swing beside it); gap_max: largest gap where the "
          "reference has contact, window mean; depth_max: deepest node inside the other body, window maximum; "
          "tunnelled: nodes through the other body; all in mm. Time: detection plus elimination, µs per step, "
          "median of %d runs (range over them)%s. Stability: %s; swing: the window's max - min of "
          "the position error (the class's chatter is the nodes' motion, not this: chatter, the largest node's motion about its window mean, against L, the length it is judged by, and injection, the contact's net work per time scale over the stored energy, are the figures the class was decided on, with the kinetic energy's growth in the CSV); tunnelled: nodes through the other body, window maximum. Useless, whatever "
          "the stability: \"%s\" (more than %d nodes through the other body) or \"%s\" (position error "
          "not at least %g %% below the run without contact force's, nor depth %g %% below it at no larger "
          "error). The Pareto front (error against time) is drawn from the evidence only: stable and not "
          "useless. A row is off it when another is no worse on both and better beyond the noise on one "
          "(error: the larger of %g %% of it, the two swings summed and the floor of the references the two rows "
          "are measured against; time: the "
          "medians apart and the ranges over the runs disjoint); rows within the noise of each other on both "
          "stay on it together. Every row is listed with its rho and reason. Made by "
          "`scripts/study.py accuracy`.\n"
          % (STUDY_EVERY, repeats, ": timing runs that each do the same work (the scene's steps, no settling, no "
             "references), executed one at a time; the error run is not timed; the pooled mean and the median 99th "
             "percentile in the CSV" if protocol else ": the first run settled and measured by CGAL, the others "
             "the scene's steps only, two at a time (the protocol before issue 32's; rerun the study for the "
             "new one)", rules.stability_source(rows), rules.TUNNELS,
             rules.WRITTEN.tunnel_limit, rules.NO_HELP, 100 * (1 - rules.WRITTEN.helps),
             100 * (1 - rules.WRITTEN.helps), 100 * rules.WRITTEN.tie)]
    for scene in scenes(a):
        sr = [r for r in rows if r["scene"] == scene]
        front = rules.pareto([r for r in sr if r["config"] != NO_FORCE], floor=kind_floor_mm(a, scene))
        for r in front:
            r["front"] = "yes"
        md.append("\n## %s\n\n%s\n\n" % (scene, front_text(sr, front, kind_floor_mm(a, scene))))
        md.append(step_front_text(a, scene))
        md.append(writers.md_table(sorted(sr, key=lambda r: (r["stable"] != "yes", bool(r["useless"]),
                                                            r["pos_err_max_mm"])),
                                   ["config", "eliminator", "force", "stability", "useless", "reference", "pos_err_max_mm",
                                    "pos_err_max_one_sided_mm", "pos_err_max_both_ways_mm", "pos_err_amp_mm",
                                    "gap_max_mm", "depth_max_mm",
                                    "tunnelled", "chatter_amp_mm", "chatter_length_mm", "injection_share",
                                    "t_contact_us", "t_contact_range", "front", "why_unstable"],
                                   ["method", "elim.", "force", "stability", "useless", "reference",
                                    "pos. error max (mm)", "against one-sided (mm)", "against both ways (mm)",
                                    "error swing (mm)", "gap max (mm)", "depth max (mm)", "tunnelled",
                                    "chatter (mm)", "L (mm)", "injection",
                                    "detect+elim (µs/step)", "range", "front", "why unstable"]))
        md.append(notes(sr))
        plot_pareto(a, scene, sr, front)
    writers.write_csv(os.path.join(a.results, "accuracy_time.csv"), rows, columns_of(COLUMNS, rows))
    with open(table_path(a, "accuracy_time.md"), "w") as f:
        f.write("".join(md))
    order = scenes(a)
    fr = [dict(r, scene=r["scene"].replace("_", " ")) for r in sorted(
        (r for r in rows if r["front"] == "yes"),
        key=lambda r: (order.index(r["scene"]) if r["scene"] in order else len(order), r["t_contact_us"]))]
    with open(table_path(a, "accuracy_time_front.tex"), "w") as f:
        f.write(writers.tex_table(fr, ["scene", "config", "eliminator", "force", "pos_err_max_mm", "gap_max_mm",
                                       "t_contact_us", "t_contact_range"],
                                  ["scenario", "method", "elim.", "force", "pos. err. (mm)", "gap (mm)",
                                   "detect+elim ($\\mu$s)", "range (%d runs)" % repeats],
                                  "Pareto front of error against time (evidence only; ties within the noise kept)"))


def step_front_text(a, scene):
    """The front over the integrator and the step (realtime_grid.csv's column front: the scene's exact
    method explicit and implicit at each step, the error's window maximum against the wall seconds per
    simulated second on one thread) in one paragraph, what each millisecond buys; "" without the file
    or the scene."""
    rows = [r for r in read_rows_or_none(a, "realtime_grid.csv") if r.get("scene") == scene]
    front = sorted((r for r in rows if r.get("front") == "yes"), key=lambda r: reader.num(r.get("wall_per_sim_s")))
    if not front:
        return ""
    def err(r):
        m = reader.num(r.get("pos_err_max_max_mm"))
        return m if m == m else reader.num(r.get("pos_err_max_mm"))
    items = ["%s at %.3g ms: %.3g s, %.3g mm" % ("implicit" if r.get("integrator") == "implicit_euler" else "explicit",
                                                1e3 * reader.num(r.get("dt")), reader.num(r.get("wall_per_sim_s")),
                                                err(r)) for r in front]
    return ("Over the integrator and the step (realtime_grid.csv: %s, wall seconds per simulated second on one "
            "thread and the error's window maximum; %d points of %d on the front): %s.\n\n"
            % (str(front[0].get("method")), len(front), len(rows), "; ".join(items)))


def read_rows_or_none(a, name):
    """A study's CSV in --results, [] without it."""
    return reader.read_csv(os.path.join(a.results, name), text=reader.STUDY_TEXT | {"point", "integrator", "method",
                                                                                     "front"}, missing=[]) or []


def front_text(rows, front, floor):
    """One scene's front in words: its size, the rows it is drawn from, and how it changes when up to
    10 tunnelled nodes are allowed (the robustness study's variant), with no relative tie and no
    floor, and under strict dominance on the figures as written (no noise at all)."""
    runs = [r for r in rows if r["config"] != NO_FORCE]
    stable = [r for r in runs if r["stable"] == "yes"]
    useless = [r for r in stable if r["useless"]]
    loose = rules.pareto(runs, floor=floor, rule=rules.TableRules(tunnel_limit=10))
    no_tie = rules.pareto(runs, floor=0.0, rule=rules.TableRules(tie=0.0))
    ok = [r for r in runs if rules.is_evidence(r)]
    strict = [r for r in ok if not any(
        o is not r and o["pos_err_max_mm"] <= r["pos_err_max_mm"] and o["t_contact_us"] <= r["t_contact_us"]
        and (o["pos_err_max_mm"] < r["pos_err_max_mm"] or o["t_contact_us"] < r["t_contact_us"]) for o in ok)]
    floors = ("reference floors %.3g mm one-sided, %.3g mm both ways" % (floor.by["one-sided"], floor.by["both ways"])
              if isinstance(floor, rules.KindFloor) else "reference floor %.3g mm" % floor)
    return ("Front: %d points, from %d stable runs of %d less the %d useless ones (%s). "
            "Allowing up to 10 tunnelled nodes it would have %d points; with no relative tie and no floor "
            "(the swings and the times' ranges still counted) %d; under strict dominance on the figures "
            "as written %d." % (len(front), len(stable), len(runs), len(useless), floors, len(loose), len(no_tie),
                                len(strict)))


PARETO_FLOOR_MM = 1e-3  # errors below it are drawn at it (log scale)


def pareto_xy(r):
    """Where a row is drawn: (time, error), the time at least 0.1 µs, the error between
    PARETO_FLOOR_MM and PARETO_CAP_MM."""
    return max(r["t_contact_us"], 0.1), min(max(r["pos_err_max_mm"], PARETO_FLOOR_MM), PARETO_CAP_MM)


def pareto_marks(ax, shown, front):
    """A marker per configuration (see plot_pareto); (the points drawn, how many are off the scale)."""
    pts, off = [], 0
    for r in shown:
        x, y = pareto_xy(r)
        ok = r["stable"] == "yes"
        fill = (USELESS_FILL if r.get("useless") else DETECTOR_COLOUR.get(r["detector"], "gray")) if ok else "none"
        capped = r["pos_err_max_mm"] > PARETO_CAP_MM
        off += capped
        c = DETECTOR_COLOUR.get(r["detector"], "gray")
        user = is_user_row(r)  # a user's method (--method): a star, named beside it
        ax.scatter(x, y, marker=USER_MARKER if user else ELIMINATOR_MARKER.get(r["eliminator"], "D"),
                   s=(60 if r in front else 40) if user else 26 if r in front else 14,
                   facecolor=fill, edgecolor="k" if r in front else c, linewidth=0.7,
                   zorder=4 if r in front else 3, clip_on=False)
        if user:
            ax.annotate(r["method"], (x, y), xytext=(4, 3), textcoords="offset points", fontsize=style.SMALL,
                        zorder=6)
        if ok and r.get("useless"):  # marked apart: never a point of the front
            ax.scatter(x, y, marker="x", s=10, color="k", linewidth=0.6, zorder=5, clip_on=False)
        if capped:
            ax.annotate("", xy=(x, y), xytext=(0, -9), textcoords="offset points", zorder=2,
                        arrowprops=dict(arrowstyle="->", lw=0.6, color=c, shrinkA=0, shrinkB=3))
        pts.append((x, y))
    return pts, off


def pareto_axes(ax, scene, off):
    """Log scales, room above the blown-up runs (`off` of them), labels, title and grid."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    style.plain_log_ticks(ax.xaxis, ax.yaxis)
    if off:
        ax.set_ylim(top=2.0 * PARETO_CAP_MM)  # room above the blown-up runs, drawn at the cap
    ax.set_xlabel("detection + elimination (µs per step)")
    ax.set_ylabel("largest position error (mm)")
    ax.set_title(scene.replace("_", " "))
    ax.grid(True, which="major", alpha=0.35)
    ax.grid(True, which="minor", alpha=0.12)


def pareto_marks_key(key, rows, base, off):
    """The key of what the marks mean, in two columns (the legend fills column by column): colours
    and hollow; shapes, front, no force, off scale."""
    from matplotlib.lines import Line2D
    col1 = [Line2D([], [], ls="none", marker="o", ms=5, mfc=DETECTOR_COLOUR.get(d, "gray"), mec="none", label=d)
            for d in sorted({r["detector"] for r in rows})]
    col1.append(Line2D([], [], ls="none", marker="o", ms=5, mfc="none", mec="0.3", label="not stable (hollow)"))
    if any(r["stable"] == "yes" and r.get("useless") for r in rows):
        col1.append(Line2D([], [], ls="none", marker="x", ms=4, mew=0.8, color="k",
                           label="stable but useless"))
    col2 = [Line2D([], [], ls="none", marker=ELIMINATOR_MARKER[e], ms=5, mfc="0.5", mec="none", label=e)
            for e in ELIMINATOR_MARKER if any(r["eliminator"] == e and not is_user_row(r) for r in rows)]
    if any(is_user_row(r) for r in rows):  # named beside the point; the overrides under the figure
        col2.append(Line2D([], [], ls="none", marker=USER_MARKER, ms=7, mfc="0.5", mec="k", mew=0.5,
                           label="yours (--method)"))
    col2.append(Line2D([], [], color="k", lw=0.7, marker="o", ms=5, mfc="0.5", mec="k", label="front (evidence)"))
    if base:
        col2.append(Line2D([], [], color="0.45", lw=0.7, ls=":", label="no contact force"))
    if off:
        col2.append(Line2D([], [], ls="none", marker="$\\uparrow$", ms=6, color="0.3",
                           label="%d above %g m (blown up)" % (off, PARETO_CAP_MM / 1e3)))
    n = max(len(col1), len(col2))
    blank = [Line2D([], [], ls="none", label=" ")]
    handles = col1 + blank * (n - len(col1)) + col2 + blank * (n - len(col2))
    leg = key.legend(handles=handles, loc="upper left", ncol=2, frameon=False, fontsize=style.SMALL,
                     handletextpad=0.5, columnspacing=0.8, borderaxespad=0.0, title="marks", alignment="left",
                     title_fontproperties={"weight": "bold", "size": style.SMALL})
    key.add_artist(leg)


USER_MARKER = "*"  # a user's method's point (study.py --method)


def user_method_note(rows):
    """The figure's note of the user's methods (--method): each name and its overrides, wrapped; ""
    without any."""
    import textwrap
    out, seen = [], set()
    for r in rows:
        if is_user_row(r) and r["method"] not in seen:
            seen.add(r["method"])
            out.append(textwrap.fill("%s (--method): %s" % (r["method"], r.get("overrides", "")), 120,
                                     break_on_hyphens=False))
    return "\n".join(out)


def pareto_front_key(key, fr, labels):
    """The key of the front's points (fr, by time), by their numbers."""
    from matplotlib.lines import Line2D
    entries = [Line2D([], [], ls="none", label="%s  %s, %s, %s: %.3g mm, %s µs" % (
        labels[k], r["config"], r["eliminator"], r["force"], r["pos_err_max_mm"],
        ("%.0f" if r["t_contact_us"] >= 100 else "%.3g") % r["t_contact_us"])) for k, r in enumerate(fr)]
    if entries:
        key.legend(handles=entries, loc="lower left", frameon=False, fontsize=style.SMALL, handlelength=0,
                   handletextpad=0, borderaxespad=0.0, title="front, by time", alignment="left",
                   title_fontproperties={"weight": "bold", "size": style.SMALL})


def plot_pareto(a, scene, rows, front):
    """Error against time, one marker per configuration (colour: detector, shape: eliminator,
    hollow: unstable, grey fill and a cross: stable but useless, i.e. tunnels or no better than no
    force: drawn apart, never a point of the front); the front of the evidence as a staircase with its points
    numbered 1, 2, ... by time and named in the key beside the axes. Printed at the text width."""
    plt = style.pyplot()
    note = user_method_note(rows)
    fig = plt.figure(figsize=(style.TEXT, 2.9 + (0.15 + 0.12 * (note.count("\n") + 1) if note else 0.0)),
                     layout="constrained")
    gs = fig.add_gridspec(1, 2, width_ratios=[1.3, 1.0])
    ax = fig.add_subplot(gs[0])
    key = fig.add_subplot(gs[1])
    key.axis("off")
    base = [r for r in rows if r["config"] == NO_FORCE and not math.isnan(r["pos_err_max_mm"])]
    rows = [r for r in rows if r["config"] != NO_FORCE]
    shown = [r for r in rows if not (math.isnan(r["pos_err_max_mm"]) or math.isnan(r["t_contact_us"]))]
    pts, off = pareto_marks(ax, shown, front)
    fr = sorted(front, key=lambda r: (r["t_contact_us"], r["pos_err_max_mm"]))
    if fr:
        ax.step([pareto_xy(r)[0] for r in fr], [pareto_xy(r)[1] for r in fr], where="post", color="k", lw=0.7,
                zorder=2)
    for r in base:  # the error with contact detected and never pushed: a useful setting is below it
        ax.axhline(min(max(r["pos_err_max_mm"], PARETO_FLOOR_MM), PARETO_CAP_MM), color="0.45", lw=0.7, ls=":",
                   zorder=1)
    pareto_axes(ax, scene, off)
    # Key: what the marks mean, then the front's points by number.
    pareto_marks_key(key, rows, base, off)
    labels = ["%d" % (k + 1) for k in range(len(fr))]
    pareto_front_key(key, fr, labels)
    stair = [pareto_xy(fr[0])] if fr else []
    for r0, r1 in zip(fr[:-1], fr[1:]):
        stair += [(pareto_xy(r1)[0], pareto_xy(r0)[1]), pareto_xy(r1)]
    style.place_labels(ax, [pareto_xy(r) for r in fr], labels,
                       avoid=[p for p in pts if p not in [pareto_xy(r) for r in fr]], lines=[stair])
    if note:
        fig.supxlabel(note, fontsize=style.SMALL, ha="left", x=0.01)
    style.save(fig, figure_path(a, "pareto_%s" % scene), width=style.TEXT)


def plots(a):
    """The tables and Pareto figures again from accuracy_time.csv (nothing is run): helps, useless
    and the front judged again under the current rules."""
    write(a, read_rows(a, "accuracy_time.csv"))
