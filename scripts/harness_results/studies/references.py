"""study.py references: the converged reference solutions every study is judged against.

Each bundled scene both ways (the answer of physics) and one way (the paper's model keeps only the
guest's nodes out of the host), and one scene on a refined mesh (its change from the base mesh: the
mesh's share of every error) -> results/references/<name>/ (summary.json with every level of the
loop, surfaces.csv: the settled reference), references.csv, references_differences.csv,
tables/references.{md,tex}. Hours; not run by scripts/reproduce.sh.
"""

import math
import os

from .. import reader, runner, writers
from .common import SCENES, refine_sets, table_path

REFINED_SCENE = "sphere_collision"


def reference_runs():
    """(name, scene, extra harness reference arguments) of every committed reference."""
    out = []
    for scene in SCENES:
        out.append((scene, scene, ["--min-levels", "4"]))
        out.append((scene + "_one_sided", scene, ["--one-sided", "--min-levels", "4"]))
    refined = runner.sets_args(refine_sets(REFINED_SCENE, 2)) + ["--dt-divide", "2"]
    out.append((REFINED_SCENE + "_refined", REFINED_SCENE, refined))
    return out


def surface_difference(a_dir, b_dir, match_rest=False):
    """Largest distance (m) between the settled surfaces of two references: vertex by vertex (the same
    mesh), or (match_rest) at the vertices of the first whose rest position the second has too (a
    mesh refined by subdivision keeps its base vertices); and how many vertices were compared."""
    A, B = reader.load_surfaces(a_dir), reader.load_surfaces(b_dir)
    worst, n = 0.0, 0
    for body, va in A.items():
        vb = B.get(body, [])
        if not match_rest:
            for p, q in zip(va, vb):
                worst, n = max(worst, math.dist(p[:3], q[:3])), n + 1
            continue
        at = {tuple(round(c, 12) for c in q[3:6]): q for q in vb}
        for p in va:
            q = at.get(tuple(round(c, 12) for c in p[3:6]))
            if q is not None:
                worst, n = max(worst, math.dist(p[:3], q[:3])), n + 1
    return worst, n


COLUMNS = ["reference", "level", "dt", "stiffness", "substeps_max", "h_over_dt_crit_min", "guard_violations", "steps",
           "settled", "residual", "change_mm", "order", "error_estimate_mm", "wall_s", "converged", "floor_mm", "floor_rule"]


def reference_rows(name, summary):
    """references.csv's rows (COLUMNS) of the reference `name` (its summary.json): one per level, the
    last with its convergence and floor."""
    rows = []
    levels, converged = reader.reference_levels(summary)
    floor, why = reader.reference_floor(summary)
    for lv in levels:
        dt_crit_min = reader.num(lv.get("dt_crit_min"))
        rows.append({"reference": name, "level": lv["level"], "dt": lv["dt"], "stiffness": lv["stiffness"],
                     "substeps_max": lv.get("max_substeps"), "guard_violations": lv.get("guard_violations"),
                     "h_over_dt_crit_min": lv["dt"] / reader.num(lv.get("max_substeps"), 1) / dt_crit_min if dt_crit_min > 0 else float("nan"),
                     "steps": lv["steps_run"], "settled": lv["settled"], "residual": lv["residual"],
                     "change_mm": 1e3 * reader.num(lv["change_max"]), "order": reader.num(lv.get("order")),
                     "error_estimate_mm": 1e3 * reader.num(lv.get("error_estimate")), "wall_s": lv["wall_s"],
                     "converged": converged if lv is levels[-1] else "",
                     "floor_mm": 1e3 * floor if lv is levels[-1] else float("nan"),
                     "floor_rule": why if lv is levels[-1] else ""})
    return rows


def run(a):
    rows = []
    for name, scene, extra in reference_runs():
        work = os.path.join(a.results, "sweeps", "references", name)
        dest = os.path.join(a.results, "references", name)
        runner.reference(a, scene, work, extra)
        runner.install_reference(work, dest)
        rows += reference_rows(name, reader.load_summary(dest))
    writers.write_csv(os.path.join(a.results, "references.csv"), rows, COLUMNS)
    # How far apart the answers are: one way against both ways (same mesh), refined against base.
    diffs = []
    for scene in SCENES:
        d, n = surface_difference(os.path.join(a.results, "references", scene),
                                  os.path.join(a.results, "references", scene + "_one_sided"))
        diffs.append({"comparison": "%s: one way against both ways" % scene, "difference_mm": 1e3 * d, "vertices": n})
    d, n = surface_difference(os.path.join(a.results, "references", REFINED_SCENE),
                              os.path.join(a.results, "references", REFINED_SCENE + "_refined"), match_rest=True)
    diffs.append({"comparison": "%s: mesh refined (x2) against base, at the base vertices" % REFINED_SCENE,
                  "difference_mm": 1e3 * d, "vertices": n})
    writers.write_csv(os.path.join(a.results, "references_differences.csv"), diffs,
                      ["comparison", "difference_mm", "vertices"])
    heads = ["reference", "level", "dt (s)", "k_c (N/m)", "substeps (max)", "h / dt_crit (min)", "guard violations",
             "steps", "settled", "residual", "change (mm)", "order", "error estimate (mm)", "wall (s)", "converged",
             "floor (mm)", "floor rule"]
    with open(table_path(a, "references.md"), "w") as f:
        f.write("# Reference solutions\n\nExact detection (CGAL), contact both ways (`_one_sided`: the guest's nodes "
                "kept out of the host only, as the paper's model does), penalty k_c x depth with barycentric "
                "reactions; each level halves dt and doubles k_c over the same physical time, under the stability "
                "guard `substep` (no substep above 0.9 dt_crit, the penalty's stiffness counted; h / dt_crit is the "
                "substep over the smallest dt_crit the guard saw), and settles to the scene's own tolerance (the "
                "one its runs settle to); change = largest distance of a surface vertex between the level and the "
                "one before; order = log2 of the ratio of the last two changes; error estimate = change / "
                "(2^order - 1) (Richardson). Converged when the change is below 0.05 mm after at least the "
                "levels asked for (four here; three for the refined mesh). floor: what an error measured against the "
                "reference cannot resolve (reader.reference_floor: the last change when the last order lies in "
                "0.5 to 4, else the largest of the last two changes); the claims widen an error's interval by it. `%s_refined`: the scene on a mesh refined once (dt halved). Made by `scripts/study.py "
                "references`.\n\n" % REFINED_SCENE + writers.md_table(rows, COLUMNS, heads) +
                "\n\n## How far apart the answers are\n\n" +
                writers.md_table(diffs, ["comparison", "difference_mm", "vertices"],
                                 ["comparison", "largest difference (mm)", "vertices compared"]))
    with open(table_path(a, "references.tex"), "w") as f:
        f.write(writers.tex_table([dict(r, reference=r["reference"].replace("_", " ")) for r in rows],
                                  ["reference", "level", "dt", "stiffness", "h_over_dt_crit_min", "steps", "change_mm",
                                   "order", "converged"],
                                  ["reference", "level", "$\\Delta t$ (s)", "$k_c$ (N/m)", "$h/\\Delta t_{crit}$",
                                   "steps", "change (mm)", "order", "converged"], "The reference loop"))
