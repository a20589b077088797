"""study.py orient: claim (a) without its confound. The paper's line points from the host node to the
guest node, its plane agrees with the host's outward normals; `orient` makes both the same either
way, over the force x voxel grid of the voxel model on the implant (the claim's scene) -> orient.csv,
tables/orient.md (the verdict is in claims.md).
"""

import os

from .. import reader, runner, writers
from .common import (config_sets, figures, force_label, mark_useless, read_rows, reference_of_kind, table_path,
                     with_both_kinds)
from .common import columns_of

ORIENT_SCENE = "implant_expansion"
# The equal-footing grid (accuracy.FOOTING_VOXELS: voxels at and above the host's node spacing).
ORIENT_FORCES = ["0.001", "0.003", "0.01", "auto"]
ORIENT_VOXELS = [0.008, 0.016]


def run(a):
    rows, configs = [], []
    kind, ref, other = reference_of_kind(a, ORIENT_SCENE, False)
    for force in ORIENT_FORCES:
        for voxel in ORIENT_VOXELS:
            for elim in ["line", "plane"]:
                for o in ["guest", "outward"]:
                    sets = config_sets("voxel", voxel, elim, force, ['contacts.0.orient="%s"' % o])
                    folder = "orient/%s/%s_%s_%g_%s" % (ORIENT_SCENE, elim, force_label(force), 1e3 * voxel, o)
                    configs.append(((force, voxel, elim, o), ORIENT_SCENE, folder, sets))
    for (force, voxel, elim, o), s in runner.run_configs(a, configs, {ORIENT_SCENE: (ref, other)}):
        row = dict(figures(s), scene=ORIENT_SCENE, eliminator=elim, orient=o, force=force_label(force),
                   voxel_mm=1e3 * voxel, max_depth_peak_mm=reader.pair_figures(s)["max_depth_peak_mm"])
        rows.append(with_both_kinds(row, s, kind))
    write(a, rows)


COLUMNS = ["scene", "eliminator", "orient", "force", "voxel_mm", "stable", "stability", "why_unstable", "pos_err_max_mm",
           "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "tunnelled", "true_pen_final", "recall",
           "t_contact_us", "helps", "useless", "reference", "pos_err_max_one_sided_mm", "pos_err_max_both_ways_mm",
           "settled", "contact_power_ratio", "rho_norm"]


def write(a, rows):
    """orient.csv and tables/orient.md from the study's rows (helps and useless: common.mark_useless)."""
    mark_useless(a, rows)
    writers.write_csv(os.path.join(a.results, "orient.csv"), rows, columns_of(COLUMNS, rows))
    md = ["# Claim (a) without its confound: line and plane, each oriented both ways\n\n",
          "The voxel model on %s: line and plane with `orient` `guest` (pushed from the host node, or the plane, "
          "toward the guest node: the paper's line) and `outward` (agreeing with the host's outward normals: the "
          "paper's plane), over forces %s and voxels %s mm. Errors over the final window (mm: rules.py) against the "
          "reference of the model's kind (one-sided where the scene has one: `reference`; the two-sided error beside "
          "it); untimed runs two at a time: the time is indicative only; useless (whatever the stability): tunnels, or no better than no force. "
          "Made by `scripts/study.py orient`; the verdict is in claims.md.\n\n" % (
              ORIENT_SCENE, ", ".join(force_label(f) for f in ORIENT_FORCES), ", ".join("%g" % (1e3 * v) for v in ORIENT_VOXELS)),
          writers.md_table(rows, ["force", "voxel_mm", "eliminator", "orient", "stable", "useless", "pos_err_max_mm",
                                  "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "t_contact_us",
                                  "why_unstable", "reference", "pos_err_max_both_ways_mm"],
                           ["force", "voxel (mm)", "elim.", "orient", "stable", "useless", "pos. error (mm)", "gap (mm)",
                            "depth (mm)", "peak depth (mm)", "pen. final", "detect+elim (µs, untimed)", "why unstable",
                            "reference", "pos. error both ways (mm)"])]
    with open(table_path(a, "orient.md"), "w") as f:
        f.write("".join(md))


def plots(a):
    """orient.csv and its table again from the CSV (nothing is run): helps and useless judged again."""
    write(a, read_rows(a, "orient.csv"))
