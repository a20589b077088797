"""The paper's "future work", the completed voxel model (detector voxel_exact: the grid of the paper
whose voxels also hold the host's triangles, an exact inside test and the nearest face), judged on
results/accuracy_time.csv: per scenario, its most accurate setting that is evidence (the fastest among
those within the noise of the least error: counts.best_of) against the most accurate
stable exact method (CGAL or hashing) of its kind (one-sided or both ways) with the same response
(eliminator and force: the completed model is a detector): for the claim "both fast and right"
when its position error is within the noise of that method's (or smaller) and its detection and
elimination is faster than the fastest exact setting that reaches its error, beyond the repeats'
spread; within the noise when as accurate and the two times' ranges over the repeats overlap; against
it when less accurate or slower beyond the spread; not judged without a setting that is evidence
(rules.py: stable, helps, tunnels nothing).
"""

import math

from .. import rules
from ..counts import best_of
from .c_restrictions import accuracy_rows
from .common import SCENE_ORDER, Verdict, figure, floor_mm, scene_cell, tally_macros, verdict_line

EXACT = ["cgal", "hash"]


def judge(ctx):
    rows = accuracy_rows(ctx)
    head = ["## The completed model (voxel_exact): both fast and right?", ""]
    if not rows:
        return Verdict("completed", rules.NOT_TESTED, head + ["Not tested: results/accuracy_time.csv is missing.", ""])
    md = head + ["Per scenario: voxel_exact's most accurate stable setting against the most accurate stable exact "
                 "method (CGAL, hashing) of the same kind (one-sided or both ways: each row's error is against the "
                 "reference of its kind) with the same response (eliminator and force: voxel_exact is a detector, "
                 "another response is another method); then against the fastest exact setting at least as accurate as it (within "
                 "the noise).", "",
                 "| scenario | voxel_exact | error (mm) | µs | best exact | error (mm) | fastest exact as accurate | µs | "
                 "speed-up | outcome |", "|---|---|---:|---:|---|---:|---|---:|---:|---|"]
    outcomes, speedups = [], []
    for scene in SCENE_ORDER:
        floor = floor_mm(ctx, scene, of_kind=True)
        sr = [r for r in rows if r["scene"] == scene and rules.is_evidence(r) and not math.isnan(r["pos_err_max_mm"])]
        ve = [r for r in sr if r["detector"] == "voxel_exact"]
        ex = [r for r in sr if r["detector"] in EXACT]
        if not ve or not ex:
            outcomes.append(rules.NOT_STABLE)
            md.append("| %s | none is evidence | | | | | | | | not judged |" % scene)
            continue
        # the most accurate, the fastest among those within the noise of the least error (counts.best_of,
        # the report's tie-break: the floors of the references of their kinds)
        v = best_of(ve, floor)
        # errors are against the reference of each row's kind: compare like with like (the exact
        # methods of voxel_exact's kind, one-sided or both ways), all of them where there is none
        ex = [r for r in ex if r.get("reference") == v.get("reference")] or ex
        # and with the same response (eliminator and force): voxel_exact is a detector, and another
        # response is another method (CGAL with projection against voxel_exact with the penalty would
        # compare the responses); all of its kind where no exact method has its response
        ex = [r for r in ex if r.get("eliminator") == v.get("eliminator") and r.get("force") == v.get("force")] or ex
        e = best_of(ex, floor)
        right = rules.decide(v, e, floor=floor) in ("a", rules.WITHIN_NOISE)
        limit = v["pos_err_max_mm"] + rules.noise(v, v, floor=floor)
        rivals = [r for r in ex if r["pos_err_max_mm"] <= limit]
        f = min(rivals, key=lambda r: r["t_contact_us"]) if rivals else None
        speed = "a" if f is None else rules.time_decide(v, f, "t_contact")
        # less accurate: against; as accurate: by the time, its spread over the repeats the noise
        o = "b" if not right else {"a": "a", "b": "b"}.get(speed, rules.WITHIN_NOISE)
        outcomes.append(o)
        if f is not None and v["t_contact_us"] > 0:
            speedups.append(f["t_contact_us"] / v["t_contact_us"])
        md.append("| %s | %s | %s | %.3g | %s | %s | %s | %s | %s | %s |" % (
            scene_cell(ctx, scene, of_kind=True), "%s, %s" % (v["config"], v["force"]), figure(v), v["t_contact_us"], "%s, %s" % (e["config"], e["force"]),
            figure(e), "%s, %s" % (f["config"], f["force"]) if f else "none", "%.3g" % f["t_contact_us"] if f else "-",
            "%.3g" % (f["t_contact_us"] / v["t_contact_us"]) if f and v["t_contact_us"] > 0 else "-",
            "for" if o == "a" else "within the noise (as accurate; the times' ranges overlap)" if o == rules.WITHIN_NOISE
            else "against (%s)" % ("less accurate" if not right else "slower beyond the spread")))
    verdict = rules.claim_verdict(outcomes, "a")
    md += ["", verdict_line("(completed model)", verdict, outcomes), ""]
    macros = tally_macros("ClaimVE", verdict, outcomes)
    macros += [("ClaimVESpeedupMin", "%.2g" % min(speedups) if speedups else "--"),
               ("ClaimVESpeedupMax", "%.2g" % max(speedups) if speedups else "--")]
    return Verdict("completed", verdict, md, macros, data=outcomes)
