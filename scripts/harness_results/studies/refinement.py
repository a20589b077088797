"""study.py refinement: the settled shape at each scene's resolution and twice as fine (box cells,
cylinder segments and rings doubled, one more icosphere subdivision; dt halved, the same physical
time) -> refinement.csv, tables/refinement.{md,tex}.
"""

import os

from .. import reader, runner, writers
from .common import refine_sets, scene_arg, scene_doc, scenes, table_path
from .common import columns_of


def run(a):
    factors = [1, 2] if not a.quick else [1]
    rows = []
    for scene in scenes(a):
        for r in factors:
            out = os.path.join(a.results, "sweeps", "refinement", scene, "x%d" % r)
            s = runner.harness(a, ["run", scene_arg(a, scene), "--out", out, "--quiet", "--dt-divide", str(r), "--set",
                                   "output.frames_every=0", "--set", 'references.solvers=["cgal"]'] +
                               runner.sets_args(refine_sets(scene, r, scene_doc(a, scene)) + a.extra_sets), out)
            disp = reader.largest_displacements(out)
            for body, d in disp.items():
                rows.append({"scene": scene, "resolution": "x%d" % r, "nodes": reader.nodes(s), "body": body,
                             "max_displacement_mm": 1e3 * d, "settled": reader.settled(s),
                             "steps": reader.steps_run(s), "forced": runner.forced_text(s)})
    for row in rows:
        base = [x for x in rows if x["scene"] == row["scene"] and x["body"] == row["body"] and x["resolution"] == "x1"]
        row["vs_x1"] = row["max_displacement_mm"] / base[0]["max_displacement_mm"] if base and base[0][
            "max_displacement_mm"] > 0 else float("nan")
    cols = ["scene", "resolution", "nodes", "body", "max_displacement_mm", "vs_x1", "settled", "steps"]
    writers.write_csv(os.path.join(a.results, "refinement.csv"), rows, columns_of(cols, rows))
    text = ("# Mesh refinement\n\nEach scenario with its default contact at its resolution and twice as fine (box "
            "cells, cylinder segments and rings doubled, one more icosphere subdivision; dt halved, every step "
            "count doubled: the same physical time). Settled shape: the largest displacement of each body's "
            "surface from its rest position. sphere_collision and cylinder_press are driven by prescribed "
            "displacements: their largest displacement is set by the drivers, so agreement there checks the "
            "kinematics, not the material; implant_expansion (pressure and gravity against the tissue) is the "
            "material check. Four times as fine (256 times the work) is beyond the time budget. "
            "Made by `scripts/study.py refinement`.\n\n")
    with open(table_path(a, "refinement.md"), "w") as f:
        f.write(text + writers.md_table(rows, cols, ["scene", "resolution", "nodes", "body",
                                                     "largest displacement (mm)", "over x1", "settled", "steps"]))
    with open(table_path(a, "refinement.tex"), "w") as f:
        f.write(writers.tex_table([dict(r, scene=r["scene"].replace("_", " ")) for r in rows],
                                  ["scene", "resolution", "nodes", "body", "max_displacement_mm", "vs_x1"],
                                  ["scenario", "mesh", "nodes", "body", "displacement (mm)", "over x1"],
                                  "Settled shape against resolution"))
