"""Claim (a), Nikolaev 2013, section 5: in implant expansion the line direction "does not work very
well"; the plane through the three nearest host points works. Judged on implant_expansion against
its converged reference, by the position error over the final window (rules.py: noise, comparison,
verdict), in three ways:
  grid      the plane against the line at each voxel size and force of the equal-footing grid
            (results/accuracy_time.csv, the paper's voxel model);
  matched   the most accurate stable plane setting against the most accurate stable line setting
            of that grid (each at its best);
  oriented  the plane against the line with both oriented the same way (results/orient.csv:
            `orient` guest and outward), which takes the rule's orientation out of the comparison.
The claim predicts the plane's error smaller.
"""

from .. import rules
from .common import Verdict, figure, floor_mm, scene_cell, tally_macros, verdict_line, word

SCENE = "implant_expansion"
NUMBERS = ["pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "tunnelled", "t_contact_us", "voxel_mm"]


def grid_rows(ctx):
    """The paper's voxel model on the implant (accuracy_time.csv): {(voxel_mm, force, eliminator): row}."""
    rows = ctx.csv("accuracy_time.csv", NUMBERS)
    return {(r["voxel_mm"], r["force"], r["eliminator"]): r for r in rows
            if r["scene"] == SCENE and r["detector"] == "voxel" and r["config"].startswith("voxel ")}


def orient_reference(rows):
    """Which reference orient.csv's rows are measured against: the one-sided (the paper's model is
    one-sided: a study run since the reference of its kind) or the two-sided one (an older file)."""
    kinds = sorted({r.get("reference") or "both ways" for r in rows}) or ["both ways"]
    return " and ".join("the two-sided one" if k == "both ways" else "the %s one" % k for k in kinds)


def judge(ctx):
    floor = floor_mm(ctx, SCENE, of_kind=True)  # accuracy_time.csv's rows: the reference of their kind
    floor_orient = floor_mm(ctx, SCENE, of_kind=True)  # orient.csv's: each row against the reference it names
    grid = grid_rows(ctx)
    orient = ctx.window_csv("orient.csv", NUMBERS)
    md = ["## (a) The plane works better than the line in implant expansion", "",
          "On `%s`, position error against the reference over the final window (mm; chatter amplitude "
          "and the reference's floor make the noise: rules.py): the grid's runs (one-sided, as the paper's model) "
          "against the reference of their kind (floor %.3g mm), the oriented runs against the reference orient.csv "
          "names (%s; floor %.3g mm). The references: %s. The claim predicts the plane's error smaller." % (
              SCENE, floor, orient_reference(orient), floor_orient.of(*orient) if hasattr(floor_orient, "of") and orient
              else floor_orient, scene_cell(ctx, SCENE, of_kind=True)), ""]
    outcomes = []
    # Grid: the same voxel and force.
    settings = sorted({(v, f) for v, f, e in grid if e == "line" and (v, f, "plane") in grid})
    md += ["### The equal-footing grid", "", "| voxel (mm) | force | line | plane | better |", "|---:|---|---:|---:|---|"]
    grid_out = []
    for v, f in settings:
        line, plane = grid[(v, f, "line")], grid[(v, f, "plane")]
        o = rules.decide(plane, line, floor=floor)
        grid_out.append(o)
        md.append("| %g | %s | %s | %s | %s |" % (v, f, figure(line), figure(plane), word(o, "plane", "line")))
    outcomes += grid_out
    # Matched: each at its best stable setting.
    best = {}
    for e in ["line", "plane"]:
        st = [r for (v, f, ee), r in grid.items() if ee == e and rules.is_evidence(r)]
        best[e] = min(st, key=lambda r: r["pos_err_max_mm"]) if st else None
    if not grid and not orient:
        return Verdict("a_plane", rules.NOT_TESTED, md + ["Not tested: results/accuracy_time.csv and "
                                                          "results/orient.csv are missing.", ""])
    md += ["", "### Each at its best", ""]
    if best["line"] and best["plane"]:
        o = rules.decide(best["plane"], best["line"], floor=floor)
        outcomes.append(o)
        md.append("The most accurate line setting that is evidence (stable, helps, tunnels nothing): %g mm, %s: %s mm; plane: %g mm, %s: %s mm. Better: %s." % (
            best["line"]["voxel_mm"], best["line"]["force"], figure(best["line"]), best["plane"]["voxel_mm"],
            best["plane"]["force"], figure(best["plane"]), word(o, "plane", "line")))
    else:
        outcomes.append(rules.NOT_STABLE)
        md.append("Not judged: %s has no setting in the grid that is evidence (stable, helps, tunnels nothing)." % " and ".join(
            e for e in ["line", "plane"] if not best[e]))
    # Oriented the same way.
    cell = {(r["force"], r["voxel_mm"], r["eliminator"], r["orient"]): r for r in orient}
    md += ["", "### Oriented the same way (results/orient.csv)", ""]
    if not orient:
        md += ["Not judged: results/orient.csv is missing or predates the window figures (rerun "
               "`scripts/study.py orient`).", ""]
    md += ["| force | voxel (mm) | orient | line | plane | better |", "|---|---:|---|---:|---:|---|"]
    orient_out = []
    for (f, v, e, o_), line in sorted(cell.items()):
        if e != "line" or (f, v, "plane", o_) not in cell:
            continue
        plane = cell[(f, v, "plane", o_)]
        o = rules.decide(plane, line, floor=floor_orient)
        orient_out.append(o)
        md.append("| %s | %g | %s | %s | %s | %s |" % (f, v, o_, figure(line), figure(plane), word(o, "plane", "line")))
    outcomes += orient_out
    verdict = rules.claim_verdict(outcomes, "a")
    t_grid, t_orient = rules.tally(grid_out), rules.tally(orient_out)
    md += ["", verdict_line("(a)", verdict, outcomes, rule="grid: %s; oriented: %s" % (
        rules.tally_text(t_grid), rules.tally_text(t_orient))), ""]
    macros = tally_macros("ClaimA", verdict, outcomes) + [
        ("ClaimAGridFor", str(t_grid["for"])), ("ClaimAGridAgainst", str(t_grid["against"])),
        ("ClaimAGridNoise", str(t_grid["noise"])), ("ClaimAGridNotJudged", str(t_grid["not judged"])),
        ("ClaimAOrientFor", str(t_orient["for"])), ("ClaimAOrientAgainst", str(t_orient["against"])),
        ("ClaimAOrientNoise", str(t_orient["noise"])), ("ClaimAOrientNotJudged", str(t_orient["not judged"])),
        ("ClaimAFloor", "%.2g" % floor)]
    macros += [("ClaimABest" + e.capitalize(), "%.3g~mm" % best[e]["pos_err_max_mm"] if best[e] else "none")
               for e in ("line", "plane")]
    return Verdict("a_plane", verdict, md, macros, data=outcomes)
