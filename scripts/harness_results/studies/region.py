"""study.py region: claim (e), "if voxels are built for large space area near penetrating bodies then
collisions are detected for any deformations": the grid's region (half, full, overlap) and its margin
under the two scenes whose bodies deform most (the implant expanding under the tissue, the cylinder
pressed in) -> region.csv, tables/region.md (the verdict is in claims.md).
"""

import os

from .. import reader, runner, writers
from .common import PAPER_ELIMINATOR, SCENE_VOXEL, config_sets, figures, table_path

REGION_SCENES = ["implant_expansion", "cylinder_press"]
REGIONS = ["half", "full", "overlap"]
MARGINS = [0, 1, 3]


def run(a):
    rows, configs = [], []
    for scene in REGION_SCENES:
        for reg in REGIONS:
            for m in MARGINS:
                sets = config_sets("voxel", SCENE_VOXEL[scene], PAPER_ELIMINATOR[scene], "auto",
                                   ['contacts.0.region="%s"' % reg, "contacts.0.margin=%d" % m])
                configs.append(((scene, reg, m), scene, "region/%s/%s_margin%d" % (scene, reg, m), sets))
    for (scene, reg, m), s in runner.run_configs(a, configs):
        rows.append(dict(figures(s), scene=scene, region=reg, margin=m, **reader.pair_figures(s)))
    cols = ["scene", "region", "margin", "stable", "why_unstable", "pos_err_max_mm", "gap_max_mm", "depth_max_mm",
            "max_depth_peak_mm", "true_pen_final", "recall", "precision", "region_rebuilds", "t_contact_us"]
    writers.write_csv(os.path.join(a.results, "region.csv"), rows, cols)
    md = ["# Claim (e): the region of the grid under large deformation\n\n",
          "The voxel model (the paper's eliminator, automatic force, the scene's voxel size) with the grid over half "
          "of the host's box facing the guest, the whole box, or the overlap of the two boxes, and 0, 1 or 3 voxels "
          "of margin. Recall: guest nodes detected among those truly penetrating (CGAL every 10 steps, over the run). "
          "Made by `scripts/study.py region`.\n\n",
          writers.md_table(rows, ["scene", "region", "margin", "stable", "pos_err_max_mm", "depth_max_mm",
                                  "max_depth_peak_mm", "true_pen_final", "recall", "region_rebuilds", "t_contact_us"],
                           ["scene", "region", "margin (voxels)", "stable", "pos. error (mm)", "depth (mm)",
                            "peak depth (mm)", "pen. final", "recall", "rebuilds", "detect+elim (µs)"])]
    with open(table_path(a, "region.md"), "w") as f:
        f.write("".join(md))
