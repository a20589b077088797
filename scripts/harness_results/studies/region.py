"""study.py region: claim (e), "if voxels are built for large space area near penetrating bodies then
collisions are detected for any deformations", on a scene built so that guest nodes leave the half
region: experiments/scenes/claims/region_wrap.json (a skin pulled around a limb, touching it down
to 10 mm below the limb's centre). The paper's voxel model with the grid over half of the host's
box facing the guest, the whole box, or the overlap of the two boxes, with 0, 1 or 3 voxels of
margin; detection alone (force 0: the skin follows its drivers, every penetration is left in place,
so every region sees the same deformation) and with the penalty force. Per run: the share of the
truly penetrating guest nodes that lie outside the grid's region (undetectable by construction),
its window mean, and recall (guest nodes detected among those truly penetrating, CGAL every 10
steps, over the run) -> region.csv, tables/region.md (the verdict is in claims.md).
"""

import os

from .. import reader, runner, writers
from .common import PENALTY, config_sets, figures, force_label, mark_useless, read_rows, table_path

REGION_SCENE = "claims/region_wrap"
# `harness run` finds the bundled scenes by name; this one by its path (relative to the checkout).
REGION_SCENE_FILE = os.path.join(reader.SOURCE, "experiments", "scenes", "claims", "region_wrap.json")
REGION_VOXEL = 0.008   # the smallest power of two above the limb's node spacing (6.7 mm)
REGIONS = ["half", "full", "overlap"]
MARGINS = [0, 1, 3]
REGION_FORCES = ["0", PENALTY]


def region_figures(s):
    """The region's figures of one run: truly penetrating guest nodes outside the grid's region
    (window mean and peak), truly penetrating guest nodes (window mean), their ratio."""
    w = reader.pair_window(s)
    out_mean = reader.window_stat(w, "outside_region")
    pen_mean = reader.window_stat(w, "true_pen_guest")
    return {"outside_mean": out_mean, "outside_peak": reader.outside_region_peak(s),
            "pen_guest_mean": pen_mean, "depth_max_mm": 1e3 * reader.window_stat(w, "depth_max", "max"),
            "outside_share": out_mean / pen_mean if pen_mean > 0 else (0.0 if pen_mean == 0 else float("nan"))}


def run(a):
    rows, configs = [], []
    for force in REGION_FORCES:
        for reg in REGIONS:
            for m in MARGINS:
                sets = config_sets("voxel", REGION_VOXEL, "line", force,
                                   ['contacts.0.region="%s"' % reg, "contacts.0.margin=%d" % m])
                folder = "region/%s_%s_margin%d" % (force_label(force), reg, m)
                configs.append(((force, reg, m), REGION_SCENE_FILE, folder, sets))
    for (force, reg, m), s in runner.run_configs(a, configs):
        # No reference for this scene: the depth is the pair's own (deepest node, window maximum).
        rows.append(dict(figures(s), scene=REGION_SCENE, force=force_label(force), region=reg, margin=m,
                         **dict(reader.pair_figures(s), **region_figures(s))))
    write(a, rows)


COLUMNS = ["scene", "force", "region", "margin", "stable", "stability", "why_unstable", "outside_share", "outside_mean",
           "outside_peak", "pen_guest_mean", "recall", "precision", "depth_max_mm", "max_depth_peak_mm", "tunnelled",
           "region_rebuilds", "t_contact_us", "useless"]


def write(a, rows):
    """region.csv and tables/region.md from the study's rows; useless: tunnels (common.mark_useless;
    the scene has no reference, so no run is judged against no force; force 0 is the baseline)."""
    mark_useless(a, rows, {})
    writers.write_csv(os.path.join(a.results, "region.csv"), rows, COLUMNS)
    md = ["# Claim (e): the region of the grid under large deformation\n\n",
          "`%s` (a skin pulled around a limb, down to 10 mm below its centre): the paper's voxel model (line, %g mm "
          "voxels) with the grid over half of the limb's box facing the skin, the whole box, or the overlap of the "
          "two boxes, and 0, 1 or 3 voxels of margin; force 0 (detection alone: every region sees the same "
          "deformation) and the penalty k = 500 N/m. outside share: truly penetrating skin nodes outside the grid's "
          "region over all truly penetrating skin nodes (window means; CGAL every 10 steps); recall: skin nodes "
          "detected among those truly penetrating, over the run; useless (whatever the stability): tunnels, or "
          "\"baseline\" (force 0: detection alone). Made by `scripts/study.py region`; the verdict is "
          "in claims.md.\n\n" % (REGION_SCENE, 1e3 * REGION_VOXEL),
          writers.md_table(rows, ["force", "region", "margin", "stability", "useless", "tunnelled", "outside_share", "outside_mean",
                                  "pen_guest_mean", "recall", "depth_max_mm", "max_depth_peak_mm", "t_contact_us"],
                           ["force", "region", "margin (voxels)", "stability", "useless", "tunnelled", "outside share", "outside (nodes)",
                            "penetrating (nodes)", "recall", "depth (mm)", "peak depth (mm)", "detect+elim (µs)"])]
    with open(table_path(a, "region.md"), "w") as f:
        f.write("".join(md))


def plots(a):
    """region.csv and its table again from the CSV (nothing is run): useless judged again."""
    write(a, read_rows(a, "region.csv"))
