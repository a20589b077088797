"""Claim (c), section 2: "all methods based on restrictions are improper ... costs much time". On
results/accuracy_time.csv (scripts/study.py accuracy: every method against the converged reference;
time = detection + elimination, median of its runs): for each scenario and exact detector (hash,
CGAL, FCL; one-sided), the restrictions, position projection and the `auto` force (a one-pass
velocity-level constraint), against the penalty force (k = 500 N/m) with the same detector. A
restriction "costs much time" when it takes over 1.1 times the penalty's time; it is "improper" when
it is unstable or its pos_err_max is over 1.1 times the penalty's. Verdict: supported when most
comparisons with a stable penalty show either, not supported when none does, partly otherwise; the
voxel model's projection is reported beside it.
"""

import math

from .common import EXACT, SCENE_ORDER, Verdict

RESTRICTION_SLOWER = 1.1   # "costs much time": over 1.1 times the penalty's time
RESTRICTION_WORSE = 1.1    # "improper": unstable, or pos_err_max over 1.1 times the penalty's
NUMBERS = ["pos_err_max_mm", "gap_max_mm", "t_contact_us", "t_step_us"]


def accuracy_rows(ctx):
    """accuracy_time.csv ([] when missing): claims (c), (d) and real time."""
    return ctx.csv("accuracy_time.csv", NUMBERS)


def comparisons(rows):
    """Restrictions (projection, auto) against the penalty force per scenario and exact detector."""
    out = []
    for scene in SCENE_ORDER:
        for det in EXACT:
            g = {(r["eliminator"], r["force"]): r for r in rows if r["scene"] == scene and r["config"] == det}
            pen = g.get(("line", "k=500"))
            if not pen:
                continue
            for name, key in (("projection", ("projection", "positions")), ("auto", ("line", "auto"))):
                r = g.get(key)
                if not r:
                    continue
                ratio = r["t_contact_us"] / pen["t_contact_us"]
                err = r["pos_err_max_mm"] / pen["pos_err_max_mm"] if pen["pos_err_max_mm"] > 0 else math.nan
                slower = ratio > RESTRICTION_SLOWER
                improper = r["stable"] != "yes" or not (err <= RESTRICTION_WORSE)
                out.append(dict(scene=scene, detector=det, restriction=name, penalty_stable=pen["stable"] == "yes",
                                stable=r["stable"] == "yes", time=r["t_contact_us"], time_pen=pen["t_contact_us"],
                                ratio=ratio, err=r["pos_err_max_mm"], err_pen=pen["pos_err_max_mm"],
                                slower=slower, improper=improper))
    return out


def judge(ctx):
    rows = accuracy_rows(ctx)
    if not rows:
        return Verdict("c_restrictions", "not tested", ["## (c) and (d)", "", "Not tested: results/accuracy_time.csv "
                                                         "is missing (scripts/study.py accuracy).", ""])
    cs = comparisons(rows)
    judged = [c for c in cs if c["penalty_stable"]]
    bad = sum(1 for c in judged if c["slower"] or c["improper"])
    if not judged:
        verdict = "not tested (no stable penalty run with an exact detector)"
    elif 2 * bad > len(judged):
        verdict = "supported"
    elif bad == 0:
        verdict = "not supported"
    else:
        verdict = "partly supported"
    vox_proj = [r for r in rows if r["detector"] == "voxel" and r["eliminator"] == "projection"]
    md = ["## (c) Restrictions are improper and cost much time", "",
          "Projection (positions moved to the surface, velocities made consistent) and the `auto` force (a one-pass "
          "velocity-level constraint) against the penalty force (k = 500 N/m), each with the same exact detector, "
          "from results/accuracy_time.csv. A restriction costs much time when it takes over %g times the "
          "penalty's detection + elimination time; it is improper when unstable or its pos_err_max is over %g "
          "times the penalty's." % (RESTRICTION_SLOWER, RESTRICTION_WORSE), "",
          "| scenario | detector | restriction | time (µs) | penalty time (µs) | ratio | pos. error (mm) | "
          "penalty pos. error (mm) | stable | penalty stable | slower | improper |",
          "|---|---|---|---:|---:|---:|---:|---:|---|---|---|---|"]
    for c in cs:
        md.append("| %s | %s | %s | %.0f | %.0f | %.2f | %.3g | %.3g | %s | %s | %s | %s |" % (
            c["scene"], c["detector"], c["restriction"], c["time"], c["time_pen"], c["ratio"], c["err"], c["err_pen"],
            "yes" if c["stable"] else "no", "yes" if c["penalty_stable"] else "no",
            "yes" if c["slower"] else "no", "yes" if c["improper"] else "no"))
    ratios = [c["ratio"] for c in judged]
    vp_stable = sum(1 for r in vox_proj if r["stable"] == "yes")
    md += ["", "**Verdict (c): %s** — of %d comparisons with a stable penalty run, %d show a restriction slower "
           "or improper (time ratios %.2f to %.2f). With the voxel model, projection is stable in %d of %d "
           "settings (its 'surface' is a voxel away)." % (verdict, len(judged), bad, min(ratios) if ratios else math.nan,
                                                      max(ratios) if ratios else math.nan, vp_stable, len(vox_proj)), ""]
    macros = [("ClaimCVerdict", verdict), ("ClaimCJudged", str(len(judged))), ("ClaimCBad", str(bad)),
              ("ClaimCRatioMin", "%.2f" % (min(ratios) if ratios else math.nan)),
              ("ClaimCRatioMax", "%.2f" % (max(ratios) if ratios else math.nan)),
              ("ClaimCVoxProjStable", str(vp_stable)), ("ClaimCVoxProj", str(len(vox_proj)))]
    return Verdict("c_restrictions", verdict, md, macros, data=cs)
