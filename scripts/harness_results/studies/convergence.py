"""study.py convergence: the voxel model's error against the reference as the voxel size halves
from 32 to 2 mm, with each scene's default force rule (defaults.json; the penalty where none) and
its paper eliminator -> convergence.csv, figures/convergence.{png,pdf}, tables/convergence.md.
The paper's model is one-sided: its errors are against the one-sided reference where the scene has
one (the limit it converges to), the two-sided reference measured beside it.
"""

import os

from .. import reader, runner, style, writers
from .common import (PENALTY, config_sets, paper_eliminator, scenes, figure_path, figures, force_label,
                     force_setting, mark_useless, read_rows, reference_of_kind, table_path, with_both_kinds)
from .common import columns_of

CONVERGENCE_VOXELS = [0.032, 0.016, 0.008, 0.004, 0.002]
CONVERGENCE_VOXELS_MM = [1e3 * v for v in CONVERGENCE_VOXELS]


def plot_convergence(a, rows):
    """Error, gap and depth against voxel size, one line per scenario (hollow markers: unstable).
    Printed at the text width."""
    from matplotlib.lines import Line2D
    plt = style.pyplot()
    fig = plt.figure(figsize=(style.TEXT, 2.6), layout="constrained")
    gs = fig.add_gridspec(2, 3, height_ratios=[1.0, 0.2])
    axes = [fig.add_subplot(gs[0, k]) for k in range(3)]
    keyax = fig.add_subplot(gs[1, :])
    keyax.axis("off")
    for k, scene in enumerate(scenes(a)):
        sr = sorted((r for r in rows if r["scene"] == scene), key=lambda r: r["voxel_mm"])
        x = [r["voxel_mm"] for r in sr]
        c = style.PALETTE[k]
        for ax, key in zip(axes, ["pos_err_max_mm", "gap_max_mm", "depth_max_mm"]):
            ax.plot(x, [r[key] for r in sr], "-", color=c, lw=1.0,
                    label="%s (%s)" % (scene.replace("_", " "), sr[0]["force"] if sr else ""))
            ax.scatter(x, [r[key] for r in sr], s=14, zorder=3, linewidth=0.8, edgecolor=c,
                       facecolor=[c if r["stable"] == "yes" else "white" for r in sr])
    for ax, t in zip(axes, ["largest position error (mm)", "largest gap (mm)", "deepest penetration (mm)"]):
        ax.set_xscale("log", base=2)
        ax.set_xticks(CONVERGENCE_VOXELS_MM)
        ax.set_xticklabels(["%g" % v for v in CONVERGENCE_VOXELS_MM])
        ax.minorticks_off()
        ax.set_xlabel("voxel size (mm)")
        ax.set_title(t)
        ax.grid(True, alpha=0.35)
    h, lab = axes[0].get_legend_handles_labels()
    h.append(Line2D([], [], ls="none", marker="o", ms=4, mfc="white", mec="0.3"))
    lab.append("unstable (hollow)")
    keyax.legend(h, lab, loc="center", ncol=2, frameon=False, borderaxespad=0.0, columnspacing=3.0)
    style.save(fig, figure_path(a, "convergence"), width=style.TEXT)


def run(a):
    d = reader.read_defaults(a.results)
    rows, jobs, index = [], [], []
    for scene in scenes(a):
        force = d.get(scene) and d[scene]["force"]
        f = force_setting(force) if force else PENALTY  # no default: the scene's own penalty
        kind, ref, other = reference_of_kind(a, scene, False)
        for v in CONVERGENCE_VOXELS:
            js = [(scene, os.path.join(a.results, "sweeps", "convergence", scene, "v%g" % (1e3 * v)),
                   config_sets("voxel", v, paper_eliminator(a, scene), f, []), (ref, other))]
            index.append((scene, v, force_label(f), kind, len(jobs)))
            jobs += js
    sums = runner.run_all(a, jobs)
    for scene, v, f, kind, i in index:
        rows.append(with_both_kinds(dict(figures(sums[i]), scene=scene, voxel_mm=1e3 * v, force=f), sums[i], kind))
    write(a, rows)


COLUMNS = ["scene", "voxel_mm", "force", "stable", "stability", "useless", "pos_err_max_mm", "pos_err_amp_mm",
           "pos_err_rms_mm", "gap_max_mm", "depth_max_mm", "tunnelled", "recall", "t_contact_us", "why_unstable", "helps",
           "reference", "pos_err_max_one_sided_mm", "pos_err_max_both_ways_mm", "settled", "contact_power_ratio", "rho_norm"]
MD_COLUMNS = COLUMNS[:COLUMNS.index("helps")] + ["reference", "pos_err_max_both_ways_mm"]


def write(a, rows):
    """convergence.csv, tables/convergence.md and the figure from the study's rows (helps and
    useless: common.mark_useless)."""
    mark_useless(a, rows)
    writers.write_csv(os.path.join(a.results, "convergence.csv"), rows, columns_of(COLUMNS, rows))
    plot_convergence(a, rows)
    cols = [c for c in MD_COLUMNS if c in rows[0]] if rows else MD_COLUMNS
    with open(table_path(a, "convergence.md"), "w") as f:
        f.write("# Convergence as the grid refines\n\nThe voxel model with each scenario's default force rule "
                "(`defaults.json`) and its eliminator; voxel size halved from 32 to 2 mm. Errors against the "
                "reference of the model's kind (one-sided where the scene has one: `reference`; the two-sided error "
                "beside it), mm; untimed runs two at a time: the time is indicative only; useless (whatever the stability): tunnels, or no better than no force. Made by "
                "`scripts/study.py convergence`.\n\n" + writers.md_table(rows, cols, cols))


def plots(a):
    """The table and figure again from convergence.csv (nothing is run): helps and useless judged again."""
    write(a, read_rows(a, "convergence.csv"))
