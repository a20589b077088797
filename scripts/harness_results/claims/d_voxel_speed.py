"""Claim (d), section 3: "collision search using space voxelization is one of the most fast".
Judged on results/accuracy_time.csv at matched error, with every setting of the equal-footing grid
that helps: per scenario, the paper's voxel model's most accurate setting that is stable and helps
(its position error at most 90 % of the run without contact force's, or its depth with a position error no
larger: rules.useful)
sets the error e_v; every method family (the paper's voxel model, the completed model voxel_exact,
spatial hashing, CGAL, FCL) is represented by its fastest stable setting whose error is at most e_v
plus the noise. The paper's model is "one of the most fast" when its time (detection and
elimination, median of the repeats) is within a factor FASTEST of the fastest family's at that
error; the comparison is against the claim when another family is faster by more than that factor
beyond the spread of the repeats, and not judged when the paper's model has no stable setting
that helps.
"""

import math

from .. import rules
from .c_restrictions import accuracy_rows
from .common import NO_FORCE, SCENE_ORDER, Verdict, floor_mm, tally_macros, verdict_line

FASTEST = 2.0
FAMILIES = [("voxel", "the paper's voxel model"), ("voxel_exact", "voxel_exact (completed)"), ("hash", "hashing"),
            ("cgal", "CGAL"), ("fcl", "FCL")]


def paper_rows(rows, scene):
    return [r for r in rows if r["scene"] == scene and r["detector"] == "voxel" and r["config"] != NO_FORCE]


def judge(ctx):
    rows = accuracy_rows(ctx)
    if not rows:
        return Verdict("d_voxel_speed", rules.NOT_TESTED, ["## (d) Voxelization is one of the fastest searches", "",
                                                           "Not tested: results/accuracy_time.csv is missing.", ""])
    md = ["## (d) Voxelization is one of the fastest searches, at matched error", "",
          "Per scenario: e_v = the position error of the paper's model's most accurate stable setting that helps "
          "(beats the run without contact force by 10 %%); each family's fastest stable setting with an error at "
          "most e_v plus the noise; the paper's model is one of the fastest within a factor %g of the fastest "
          "family (detection + elimination, median of the repeats, beyond their spread)." % FASTEST, ""]
    outcomes = []
    for scene in SCENE_ORDER:
        floor = floor_mm(ctx, scene)
        sr = [r for r in rows if r["scene"] == scene]
        base = next((r for r in sr if r["config"] == NO_FORCE), None)
        # evidence: stable, tunnels nothing, and helps (marked against `base` by the context)
        vox = [r for r in paper_rows(rows, scene) if rules.is_evidence(r) and not math.isnan(r["pos_err_max_mm"])]
        md.append("### %s" % scene)
        md.append("")
        if not vox:
            outcomes.append(rules.NOT_STABLE)
            md += ["Not judged: no setting of the paper's model is evidence: stable, helps, tunnels nothing (run without contact force: %s mm)."
                   % ("%.3g" % base["pos_err_max_mm"] if base else "-"), ""]
            continue
        best = min(vox, key=lambda r: (r["pos_err_max_mm"], r["t_contact_us"]))
        e_v = best["pos_err_max_mm"]
        limit = e_v + rules.noise(best, best, floor=floor)
        md += ["e_v = %.3g mm (%s, %s, %s); within the noise: at most %.3g mm." % (
            e_v, best["config"], best["eliminator"], best["force"], limit), "",
               "| family | fastest at e_v | error (mm) | µs per step | range | its best error (mm) |",
               "|---|---|---:|---:|---|---:|"]
        fastest = {}
        for det, name in FAMILIES:
            fam = [r for r in sr if r["detector"] == det and r["config"] != NO_FORCE and rules.is_evidence(r)
                   and not math.isnan(r["pos_err_max_mm"])]
            at = [r for r in fam if r["pos_err_max_mm"] <= limit]
            f = min(at, key=lambda r: r["t_contact_us"]) if at else None
            fastest[det] = f
            own = min((r["pos_err_max_mm"] for r in fam), default=math.nan)
            md.append("| %s | %s | %s | %s | %s | %.3g |" % (
                name, "%s, %s, %s" % (f["config"], f["eliminator"], f["force"]) if f else "none reaches it",
                "%.3g" % f["pos_err_max_mm"] if f else "-", "%.3g" % f["t_contact_us"] if f else "-",
                f["t_contact_range"] if f else "-", own))
        mine = fastest["voxel"]
        others = [f for det, f in fastest.items() if f is not None and det != "voxel"]
        against = [f for f in others if rules.time_decide(f, mine, "t_contact", factor=FASTEST) == "a"]
        o = "b" if against else "a"
        outcomes.append(o)
        md += ["", "Outcome: %s." % ("for: within %gx of every family at this error" % FASTEST if o == "a" else
                                    "against: %s faster by over %gx" % (", ".join(
                                        "%s (%s, %.3g µs)" % (f["detector"], f["config"], f["t_contact_us"])
                                        for f in against), FASTEST)), ""]
    verdict = rules.claim_verdict(outcomes, "a")
    md += [verdict_line("(d)", verdict, outcomes), ""]
    return Verdict("d_voxel_speed", verdict, md, tally_macros("ClaimD", verdict, outcomes) + [
        ("ClaimDFactor", "%g" % FASTEST)], data=outcomes)
