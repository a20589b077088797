"""study.py ablation: the voxel model's force rule and magnitude (constant 0.0005 to 0.1 N, `auto`,
penalty 125 to 2000 N/m) by voxel size (4 to 32 mm), with the scene's paper eliminator; the default
chosen by the written rule (rules.choose) among the voxels at or above the host's node spacing
(accuracy.FOOTING_VOXELS: a finer voxel misses guest nodes inside the host, and the harness warns)
-> ablation.csv, defaults.json,
figures/ablation_<scene>.{png,pdf}, tables/ablation.md, tables/ablation_defaults.tex.
"""

import json
import os

from .. import methods, reader, rules, runner, style, writers
from .accuracy import FOOTING_VOXELS
from .common import (PARETO_CAP_MM, PENALTY, columns_of, combine, config_sets, figure_path, figures, footing_voxels,
                     force_label, is_user_row, mark_useless, no_force_bases, notes, paper_eliminator, read_rows,
                     reference_of_kind, scenes, table_path, user_fields, user_methods, with_both_kinds)

ABLATION_VOXELS = [0.004, 0.008, 0.016, 0.032]
CONSTANT_FORCES = ["0.0005", "0.001", "0.003", "0.01", "0.03", "0.1"]
ABLATION_FORCES = CONSTANT_FORCES + ["auto", '{"stiffness":125}', PENALTY, '{"stiffness":2000}']


def builtin_names():
    """The grid's force columns' names, which a user's method (--method) may not take."""
    return [force_label(f) for f in ABLATION_FORCES]


def ablation_voxels(a, scene):
    """The bundled scenes' ABLATION_VOXELS; for a user's scene the powers of two from half its
    footing voxel (below the host's node spacing) to four times it."""
    f = footing_voxels(a, scene, FOOTING_VOXELS)[0] if getattr(a, "user", None) else None
    return [f / 2, f, 2 * f, 4 * f] if f else ABLATION_VOXELS


def run(a):
    """Every setting of every scene: one error run against the reference of its kind (the paper's
    model is one-sided: the one-sided reference where the scene has one), the two-sided reference
    measured beside it, and --repeats timing runs of the same work, one at a time (runner.repeated:
    the accuracy study's protocol)."""
    rows, jobs, index = [], [], []
    for scene in scenes(a):
        elim = paper_eliminator(a, scene)
        kind, ref, other = reference_of_kind(a, scene, False)
        for v in ablation_voxels(a, scene):
            for f in ABLATION_FORCES:
                js = runner.repeated(a, scene, "ablation/%s/v%g_%s" % (scene, 1e3 * v, force_label(f)),
                                     config_sets("voxel", v, elim, f, []), compare=(ref, other))
                index.append((scene, v, f, kind, len(jobs), len(js)))
                jobs += js
            for m in user_methods(a):  # study.py --method: a column of its own, at every voxel
                mkind, mref, mother = reference_of_kind(a, scene, bool(methods.value(m.sets, "contacts.0.two_sided")))
                js = runner.repeated(a, scene, "ablation/%s/v%g_%s" % (scene, 1e3 * v, methods.folder(m)),
                                     user_sets(v, elim, m), compare=(mref, mother))
                index.append((scene, v, m, mkind, len(jobs), len(js)))
                jobs += js
    base_at = len(jobs)
    kinds = {}
    for scene in scenes(a):  # the baseline: contact measured, never pushed (force 0); untimed
        kinds[scene] = kind, ref, other = reference_of_kind(a, scene, False)
        jobs.append((scene, os.path.join(a.results, "sweeps", "ablation/%s/no_force" % scene),
                     config_sets("voxel", ablation_voxels(a, scene)[0], paper_eliminator(a, scene), "0", []),
                     (ref, other), 0))
    sums = runner.run_all(a, jobs)
    baseline = {scene: with_both_kinds(figures(sums[base_at + k]), sums[base_at + k], kinds[scene][0])
                for k, scene in enumerate(scenes(a))}
    for scene, v, f, kind, i, n in index:
        user = isinstance(f, methods.Method)
        row = dict(combine(sums[i:i + n]), scene=scene, voxel_mm=1e3 * v, force=f.name if user else force_label(f),
                   eliminator=paper_eliminator(a, scene))
        if user_methods(a):
            row.update(user_fields(f) if user else {"method": "", "overrides": ""})
        rows.append(with_both_kinds(row, sums[i], kind))
    write(a, rows, baseline)


def user_sets(v, elim, m):
    """The --set overrides of a user's method at voxel `v`: the grid's (the voxel model, the scene's
    paper eliminator, one-sided, CGAL every STUDY_EVERY steps, the voxel) but its force, which is the
    scene's unless the method sets it; then the method's own (which may change any of them)."""
    return [x for x in config_sets("voxel", v, elim, "auto", []) if not x.startswith("contacts.0.force=")] + list(m.sets)


COLUMNS = ["scene", "eliminator", "voxel_mm", "force", "stable", "why_unstable", "settled", "pos_err_max_mm",
           "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "tunnelled", "contact_power_ratio", "stability",
           "t_contact_us", "t_contact_range", "recall", "precision", "helps", "useless", "reference",
           "pos_err_max_one_sided_mm", "pos_err_max_both_ways_mm", "rho_norm", "t_contact_mean_us",
           "t_contact_p99_us", "t_step_us", "t_step_mean_us", "t_step_p99_us", "repeats", "machine"]


def write(a, rows, baseline):
    """ablation.csv, tables/ablation.md, tables/ablation_defaults.tex, defaults.json and the heat
    maps from the study's rows; `baseline`: {scene: its run without contact force}, what helps and
    useless (common.mark_useless) and the default (rules.choose) are judged against."""
    mark_useless(a, rows, baseline)
    md = ["# Ablation: force rule and magnitude by voxel size (the voxel model)\n\n",
          "The paper's voxel model with its eliminator for the scenario; constant force F (N per contact), "
          "`auto`, and the depth penalty k (N/m), by voxel size. Errors against the reference (mm) and "
          "stability as in `accuracy_time.md` (%s); the paper's model is one-sided, so "
          "its errors are against the one-sided reference where the scene has one (column `reference`; the "
          "error against the two-sided reference beside it in ablation.csv); useless (whatever the stability): "
          "tunnels, or no better than no force against the same kind of reference; time: detection and "
          "elimination per step, the median over the timing runs' medians (each the same work, run one at "
          "a time, as in the accuracy study; mean and 99th percentile in ablation.csv). Made by "
          "`scripts/study.py ablation`.\n" % rules.stability_source(rows)]
    reasons = ["% The voxel model's defaults chosen by the rule (made by scripts/study.py)\n"]
    chosen = {}
    for scene in scenes(a):
        sr = [r for r in rows if r["scene"] == scene]
        grid = [r for r in sr if not is_user_row(r)]  # the default is the voxel model's: the user's methods beside it
        footing = min(footing_voxels(a, scene, FOOTING_VOXELS)) * 1e3 - 1e-9  # the default: on equal footing only
        best = chosen[scene] = rules.choose([r for r in grid if r["voxel_mm"] >= footing], baseline.get(scene))
        md.append("\n## %s (%s)\n\n" % (scene, paper_eliminator(a, scene)))
        md.append(writers.md_table(sr, ["voxel_mm", "force", "stable", "useless", "pos_err_max_mm", "gap_max_mm",
                                        "depth_max_mm", "tunnelled", "contact_power_ratio", "t_contact_us",
                                        "why_unstable"],
                                   ["voxel (mm)", "force", "stable", "useless", "pos. error max (mm)", "gap max (mm)",
                                    "depth max (mm)", "tunnelled", "contact work / energy in", "detect+elim (µs)",
                                    "why unstable"]))
        text = default_text(scene, grid, best, baseline.get(scene), footing) + fragility(grid, best,
                                                                                    baseline.get(scene), footing)
        md.append("\n" + text + "\n")
        if len(grid) < len(sr):
            md.append("\nThe user's methods (`--method`; their columns are named after them) are judged beside the grid "
                      "and are not candidates for the default.\n")
        md.append(notes(sr, "force"))
        reasons.append("\\paragraph{Default of \\code{%s}.} %s\n" % (writers.tex_escape(scene),
                                                                      writers.tex_escape(text)))
        plot_ablation(a, scene, sr)
    writers.write_csv(os.path.join(a.results, "ablation.csv"), rows, columns_of(COLUMNS, rows))
    with open(table_path(a, "ablation.md"), "w") as f:
        f.write("".join(md))
    with open(table_path(a, "ablation_defaults.tex"), "w") as f:
        f.write("\n".join(reasons))
    with open(os.path.join(a.results, "defaults.json"), "w") as f:
        json.dump({scene: ({"voxel_size": chosen[scene]["voxel_mm"] / 1e3, "force": chosen[scene]["force"],
                            "eliminator": paper_eliminator(a, scene)} if chosen[scene] else None) for scene in scenes(a)},
                  f, indent=2, sort_keys=True)
        f.write("\n")


def default_text(scene, rows, best, base, footing=0.0):
    """The rule and the default of one scene in words; `base`: the run without contact force (its
    figures against the same kind of reference as the rows: rules.same_kind_base), `footing`: the
    smallest voxel (mm) a default may have."""
    if base is None:
        return ("No run without contact force for this scenario (the accuracy study's): the default is not "
                "judged against doing nothing.")
    base = rules.same_kind_base(rows[0] if rows else {}, base)  # run() and plots() alike: the rows' kind
    stable = [r for r in rows if r["stable"] == "yes"]
    good = [r for r in stable if rules.useful(r, base)]
    out = ("Rule: among the stable settings with voxels at or above the host's node spacing that help (a position "
           "error at most %g %% of the run without contact force's, or a depth at most %g %% of its depth with a "
           "position error no larger: %.3g mm and %.3g mm here, against the %s reference), the smallest largest "
           "position error; among those within 10 %% "
           "of it, the smallest gap; among those, the fastest. %d of %d settings are stable, %d of them clearly "
           "better than no force, %d of those with voxels at or above the node spacing (%g mm). " % (
               100 * rules.WRITTEN.helps, 100 * rules.WRITTEN.helps, base["pos_err_max_mm"], base["depth_max_mm"],
               "two-sided" if (rows[0].get("reference") or "both ways") == "both ways" else "one-sided",
               len(stable), len(rows), len(good), sum(r["voxel_mm"] >= footing for r in good), round(footing, 3)))
    if best is None:
        return out + ("None qualifies: the voxel model has no default for this scenario, and CI has no accuracy "
                      "threshold for it (results/thresholds.json says why).")
    return out + ("Chosen: %s at %g mm voxels: position error %.3g mm, gap %.3g mm, depth %.3g mm, %.3g µs per "
                  "step for detection and elimination." % (best["force"], best["voxel_mm"], best["pos_err_max_mm"],
                                                            best["gap_max_mm"], best["depth_max_mm"],
                                                            best["t_contact_us"]) + tunnel_note(best))


def fragility(rows, best, base, footing):
    """Whether the default stands under the rule's other choices: every setting and the run without force against the two-sided reference (their
    pos_err_max_both_ways_mm), and how many settings qualify at all; "" when there is nothing to say."""
    if base is None:
        return ""
    on = [r for r in rows if r["voxel_mm"] >= footing]
    name = lambda r: "none" if r is None else "%s at %g mm" % (r["force"], r["voxel_mm"])
    out = []
    base_kind = rules.same_kind_base(rows[0] if rows else {}, base)
    qualify = [r for r in on if r["stable"] == "yes" and reader.present(r.get("pos_err_max_mm")) and
               rules.useful(r, base_kind)]
    if best is not None and len(qualify) == 1:
        out.append("it is the only setting that qualifies")
    two = [rules.as_two_sided(r) for r in on]
    other = rules.choose(two, rules.as_two_sided(base))
    if name(other) != name(best):
        out.append("with every run against the two-sided reference it would be %s" % name(other))
    elif best is not None:
        b2 = next(r for r in two if name(r) == name(best))
        base2 = rules.as_two_sided(base)  # b2 is two-sided too: no mapping needed
        if b2["pos_err_max_mm"] > rules.WRITTEN.helps * base2["pos_err_max_mm"]:
            out.append("against the two-sided reference it helps by depth alone (position error %.3g mm against "
                       "%.3g mm without force)" % (b2["pos_err_max_mm"], base2["pos_err_max_mm"]))
    if best is not None and reader.present(best.get("gap_max_mm")) and reader.num(best["gap_max_mm"]) > 0:
        out.append("it holds the bodies up to %.3g mm apart where the reference has them touching" % best["gap_max_mm"])
    return (" Fragility: " + "; ".join(out) + ".") if out else " The default stands under the rule's other choices."


def tunnel_note(best):
    """What the chosen default's tunnelling means: the defaults' rule does not look at it, the
    evidence rule does (rules.py)."""
    n = reader.num(best.get("tunnelled"), 0.0)
    if n <= 0:
        return ""
    return (" It tunnels %d node%s over the window: the defaults' rule does not look at tunnelling, the claims' "
            "evidence rule does, so this default is useless as evidence." % (n, "" if n == 1 else "s"))


def plot_ablation(a, scene, rows):
    """Two heat maps (position error, gap) by force rule and voxel size; the stable settings
    outlined. Printed at the text width."""
    forces = [force_label(f) for f in ABLATION_FORCES]
    users = []  # the user's methods (--method): a column each, after the grid's
    for r in rows:
        if is_user_row(r) and r["force"] not in forces:
            forces.append(r["force"])
            users.append("%s (--method): %s" % (r["method"], r.get("overrides", "")))
    voxels = sorted({r["voxel_mm"] for r in rows}) or [1e3 * v for v in ABLATION_VOXELS]
    panels = [("pos_err_max_mm", "largest position error (mm)"), ("gap_max_mm", "largest gap (mm)")]
    plt = style.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(style.TEXT, 2.35), layout="constrained")
    for k, (ax, (key, title)) in enumerate(zip(axes, panels)):
        m = [[float("nan")] * len(forces) for _ in voxels]
        stable = []
        for r in rows:
            i, j = voxels.index(r["voxel_mm"]), forces.index(r["force"])
            m[i][j] = r[key]
            if r["stable"] == "yes":
                stable.append((j, i))
        im = style.heatmap(ax, m, forces, ["%g" % v for v in voxels], title, stable, cap=PARETO_CAP_MM,
                           cap_text=">1 m")
        fig.colorbar(im, ax=ax, fraction=0.06, pad=0.02, aspect=15)
        ax.set_xlabel("force rule (F: constant, N; k: penalty, N/m)")
        if k == 0:
            ax.set_ylabel("voxel size (mm)")
    fig.suptitle("%s, %s eliminator; outlined: stable (%d of %d); >1 m: blown up" % (
        scene.replace("_", " "), paper_eliminator(a, scene), sum(r["stable"] == "yes" for r in rows), len(rows)))
    if users:
        import textwrap
        fig.supxlabel("\n".join(textwrap.fill(u, 120, break_on_hyphens=False) for u in users),
                      fontsize=style.SMALL, ha="left", x=0.01)
    style.save(fig, figure_path(a, "ablation_%s" % scene), width=style.TEXT)


def plots(a):
    """The tables, defaults and heat maps again from ablation.csv (nothing is run), against the
    accuracy study's runs without contact force (the same trajectory as the ablation's own: force 0
    pushes nothing whatever the voxel or eliminator)."""
    write(a, read_rows(a, "ablation.csv"), no_force_bases(a))
