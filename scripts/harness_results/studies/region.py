"""study.py region: claim (e), "if voxels are built for large space area near penetrating bodies then
collisions are detected for any deformations", over DEFORMATIONS a surgeon's scene produces, each a
scene built so that its deformation is the one named (experiments/scenes/claims/; the inflation is
the bundled implant_expansion): a skin wrapped around a limb (its ends pulled down and in, down to 10 mm below the limb's
centre); the same skin's ends pulled down and turned in opposite senses about its axis (twist); a
thick block pressed 14 mm down onto a thin limb while its two ends are pushed 8 mm in each
(compression, 27 % along its length, wrapping the limb below its centre); the same block's top
dragged 20 mm along x as it is pressed while its -x end sinks without moving along x (shear, 45
degrees through its thickness, sliding over the limb); the implant inflated under the tissue layer
(inflation). With force 0 the drivers make these deformations kinematically (nothing resists);
with the response on, the contact shapes them too. The host limbs are pinned along their axes:
only the inflation makes the grid follow a deforming host. The paper's voxel model (8 mm voxels, line) with the grid over
half of the host's box facing the guest, the whole box, or the overlap of the two boxes, with 0, 1
or 3 voxels of margin; detection alone (force 0: the guest follows its drivers or the implant's
pressure, every penetration is left in place, so every region sees the same deformation) and with
the penalty force (the response on). Per run: the share of the truly penetrating guest nodes that
lie outside the grid's region (undetectable by construction; window mean and peak over the run),
recall and precision (guest nodes detected among those truly penetrating, and truly penetrating
among those detected; CGAL every 10 steps, over the run), the precision of flagging every guest
node (the truly penetrating guest nodes over all guest nodes, over the measured steps) and of
flagging every guest node inside the region's box (a region that flags everything), and the
region's size in voxels (mean and peak over the measured steps) -> region.csv, tables/region.md
(the verdict is in claims.md).
"""

import os

from .. import reader, runner, writers
from .common import PENALTY, config_sets, figures, force_label, mark_useless, read_rows, table_path
from .common import columns_of


def claim_scene(name):
    """A claims scene's file (`harness run` finds the bundled scenes by name, these by path)."""
    return os.path.join(reader.SOURCE, "experiments", "scenes", "claims", name + ".json")


# (deformation, the scene's label in the CSV, what `harness run` is given)
DEFORMATIONS = [("wrap", "claims/region_wrap", claim_scene("region_wrap")),
                ("twist", "claims/region_twist", claim_scene("region_twist")),
                ("compression", "claims/region_compress", claim_scene("region_compress")),
                ("shear", "claims/region_shear", claim_scene("region_shear")),
                ("inflation", "implant_expansion", "implant_expansion")]
REGION_VOXEL = 0.008   # the smallest power of two above the wrap limb's node spacing (6.7 mm)
REGIONS = ["half", "full", "overlap"]
MARGINS = [0, 1, 3]
REGION_FORCES = ["0", PENALTY]


def region_figures(s):
    """The region's figures of one run: truly penetrating guest nodes outside the grid's region
    (window mean and peak over the run), truly penetrating guest nodes (window mean), their ratio;
    the region's size in voxels (mean and peak over the measured steps); the precision of flagging
    every guest node (truly penetrating guest nodes over all guest nodes) and of flagging every guest
    node inside the region's box (truly penetrating ones among them), over the measured steps."""
    w = reader.pair_window(s)
    out_mean = reader.window_stat(w, "outside_region")
    pen_mean = reader.window_stat(w, "true_pen_guest")
    p = s["pairs"][0]
    rv = p.get("region_voxels") or {}
    sc = p.get("scores") or {}
    guest = next((b for b in s.get("bodies", []) if b.get("name") == p.get("pair", "/").split("/")[-1]), None)
    steps = reader.num(p.get("measured_steps"))
    flag_all = ((sc["tp"] + sc["fn"]) / (steps * guest["nodes"]) if sc and guest and steps > 0 else float("nan"))
    inside = reader.num(rv.get("guest_nodes_inside"))
    flag_region = reader.num(rv.get("penetrating_inside")) / inside if inside > 0 else float("nan")
    return {"outside_mean": out_mean, "outside_peak": reader.outside_region_peak(s),
            "pen_guest_mean": pen_mean, "depth_max_mm": 1e3 * reader.window_stat(w, "depth_max", "max"),
            "outside_share": out_mean / pen_mean if pen_mean > 0 else (0.0 if pen_mean == 0 else float("nan")),
            "region_voxels_mean": reader.num(rv.get("mean")), "region_voxels_peak": reader.num(rv.get("peak")),
            "precision_flag_all": flag_all, "precision_flag_region": flag_region}


def run(a):
    rows, configs = [], []
    for deformation, label, path in DEFORMATIONS:
        for force in REGION_FORCES:
            for reg in REGIONS:
                for m in MARGINS:
                    sets = config_sets("voxel", REGION_VOXEL, "line", force,
                                       ['contacts.0.region="%s"' % reg, "contacts.0.margin=%d" % m])
                    folder = "region/%s/%s_%s_margin%d" % (deformation, force_label(force), reg, m)
                    configs.append(((deformation, label, force, reg, m), path, folder, sets))
    for (deformation, label, force, reg, m), s in runner.run_configs(a, configs):
        # No reference for these runs: the depth is the pair's own (deepest node, window maximum).
        rows.append(dict(figures(s), scene=label, deformation=deformation, force=force_label(force), region=reg,
                         margin=m, **dict(reader.pair_figures(s), **region_figures(s))))
    write(a, rows)


COLUMNS = ["scene", "deformation", "force", "region", "margin", "stable", "stability", "why_unstable", "outside_share",
           "outside_mean", "outside_peak", "pen_guest_mean", "recall", "precision", "precision_flag_all", "precision_flag_region",
           "region_voxels_mean", "region_voxels_peak", "depth_max_mm", "max_depth_peak_mm", "tunnelled", "region_rebuilds",
           "t_contact_us", "useless"]


def write(a, rows):
    """region.csv and tables/region.md from the study's rows; useless: tunnels (common.mark_useless;
    the scene has no reference, so no run is judged against no force; force 0 is the baseline)."""
    mark_useless(a, rows, {})
    writers.write_csv(os.path.join(a.results, "region.csv"), rows, columns_of(COLUMNS, rows))
    md = ["# Claim (e): the region of the grid under the deformations of a surgeon's scene\n\n",
          "Deformations: %s (scripts/harness_results/studies/region.py says how each is made). The paper's voxel "
          "model (line, %g mm voxels) with the grid over half of the host's box facing the guest, the whole box, "
          "or the overlap of the two boxes, and 0, 1 or 3 voxels of margin; force 0 (detection alone: every region "
          "sees the same deformation) and the penalty k = 500 N/m (the response on). outside share: truly "
          "penetrating guest nodes outside the grid's region over all truly penetrating guest nodes (window means); "
          "outside peak: the most outside at one measured step over the run; recall and precision over the run "
          "(CGAL every 10 steps); flag-all: the precision of flagging every guest node; flag-region: of flagging every guest node inside the region's box; region size in voxels "
          "(mean over the measured steps); untimed runs two at a time: the time is indicative only; useless (whatever the stability): tunnels, or \"baseline\" (force 0: "
          "detection alone). Made by `scripts/study.py region`; the verdict is in claims.md.\n\n" % (
              ", ".join("%s (`%s`)" % (d, l) for d, l, _p in DEFORMATIONS), 1e3 * REGION_VOXEL),
          writers.md_table(rows, ["deformation", "force", "region", "margin", "stability", "useless", "tunnelled",
                                  "outside_share", "outside_peak", "pen_guest_mean", "recall", "precision",
                                  "precision_flag_all", "precision_flag_region", "region_voxels_mean", "depth_max_mm", "max_depth_peak_mm",
                                  "t_contact_us"],
                           ["deformation", "force", "region", "margin (voxels)", "stability", "useless", "tunnelled",
                            "outside share", "outside peak", "penetrating (nodes)", "recall", "precision", "flag-all", "flag-region",
                            "region (voxels)", "depth (mm)", "peak depth (mm)", "detect+elim (µs, untimed)"])]
    with open(table_path(a, "region.md"), "w") as f:
        f.write("".join(md))


def plots(a):
    """region.csv and its table again from the CSV (nothing is run): useless judged again."""
    write(a, read_rows(a, "region.csv"))
