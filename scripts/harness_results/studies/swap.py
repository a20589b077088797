"""study.py swap: which body carries the grid (the paper leaves it open): the voxel model with host
and guest as the scene has them and swapped, with the scene's default (defaults.json) when there is
one and the paper's eliminator with the automatic force at the scene's voxel size -> swap.csv,
tables/swap.md. Both placements are measured against the two-sided reference: the one-sided
reference (`harness reference --one-sided`) is the limit of the scene's placement only (its guest
kept out of its host); the swapped placement's one-sided limit is another contact problem, so the
two-sided reference is the only one both sides of a comparison share.
"""

import os

from .. import reader, runner, writers
from .common import (STUDY_EVERY, config_sets, pair_bodies, paper_eliminator, scene_voxel, scenes, figures, force_label,
                     force_setting, mark_useless, read_rows, table_path)
from .common import columns_of

SWAP_BODIES = {"sphere_collision": ("left", "right"), "cylinder_press": ("layer", "cylinder"),
               "implant_expansion": ("implant", "tissue")}


def swap_configs(a, scene):
    """The voxel model's default of the scene (defaults.json) when there is one, and the paper's
    eliminator with the automatic force at the scene's voxel size."""
    out = [(paper_eliminator(a, scene), "auto", scene_voxel(a, scene))]
    d = reader.read_defaults(a.results).get(scene)
    if d:
        cfg = (d["eliminator"], force_setting(d["force"]), d["voxel_size"])
        if cfg not in out:
            out.insert(0, cfg)
    return out


def run(a):
    rows, configs = [], []
    for scene in scenes(a):
        host, guest = pair_bodies(a, scene, SWAP_BODIES)
        for elim, force, voxel in swap_configs(a, scene):
            for swapped in (False, True):
                h, g = (guest, host) if swapped else (host, guest)
                sets = config_sets("voxel", voxel, elim, force, ['contacts.0.host="%s"' % h, 'contacts.0.guest="%s"' % g,
                                                                 "references.every=%d" % STUDY_EVERY])
                folder = "swap/%s/%s_%s_%g_%s" % (scene, elim, force_label(force), 1e3 * voxel,
                                                  "swapped" if swapped else "as_scene")
                configs.append(((scene, elim, force, voxel, h, g, swapped), scene, folder, sets))
    for (scene, elim, force, voxel, h, g, swapped), s in runner.run_configs(a, configs):
        rows.append(dict(figures(s), scene=scene, eliminator=elim, force=force_label(force), voxel_mm=1e3 * voxel,
                         host=h, guest=g, swapped="yes" if swapped else "no",
                         max_depth_peak_mm=reader.pair_figures(s)["max_depth_peak_mm"]))
    write(a, rows)


COLUMNS = ["scene", "eliminator", "force", "voxel_mm", "host", "guest", "swapped", "stable", "stability", "why_unstable",
           "pos_err_max_mm", "pos_err_amp_mm", "tunnelled", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm",
           "true_pen_final", "recall", "precision", "t_contact_us", "helps", "useless", "settled", "contact_power_ratio",
           "rho_norm"]


def write(a, rows):
    """swap.csv and tables/swap.md from the study's rows (helps and useless: common.mark_useless)."""
    mark_useless(a, rows)
    writers.write_csv(os.path.join(a.results, "swap.csv"), rows, columns_of(COLUMNS, rows))
    md = ["# Which body carries the grid\n\n",
          "The voxel model with host and guest as the scene has them and swapped (the grid on the other body), "
          "against the scene's two-sided reference, which both placements share (references.csv says whether it "
          "converged; errors over the final window, mm; peak depth over the run; recall "
          "and precision of the guest nodes detected, CGAL every 10 steps); untimed runs two at a time: the time is "
          "indicative only; useless (whatever the stability): tunnels, or no better than no force. Made by `scripts/study.py swap`.\n\n",
          writers.md_table(rows, ["scene", "eliminator", "force", "voxel_mm", "host", "guest", "stable", "useless",
                                  "tunnelled", "pos_err_max_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final",
                                  "recall", "t_contact_us"],
                           ["scene", "elim.", "force", "voxel (mm)", "host (grid)", "guest", "stable", "useless",
                            "tunnelled", "pos. error (mm)",
                            "gap (mm)", "depth (mm)", "peak depth (mm)", "pen. final", "recall", "detect+elim (µs, untimed)"])]
    with open(table_path(a, "swap.md"), "w") as f:
        f.write("".join(md))


def plots(a):
    """swap.csv and its table again from the CSV (nothing is run): helps and useless judged again."""
    write(a, read_rows(a, "swap.csv"))
