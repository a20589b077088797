"""Claim (c), section 2: "All methods based on restrictions are improper for this case because
collision joint bound calculation is hard and costs much time." A restriction (the paper, after
Faure et al.) computes the bound of the region the two bodies share and moves the points out of it.
Judged on results/accuracy_time.csv, per scenario and detector: the restriction's cost is its
detection and projection (positions moved out along the nearest surface: the `projection`
eliminator) plus the cost of finding the bound (CGAL's corefinement of the two surfaces, timed on
the same states: t_bound_us); against the penalty force (k = 500 N/m, depth along the line) with
the same detector. A comparison goes for the claim when the restriction costs much time (over
MUCH times the penalty's, beyond the spread of the repeats) or is improper (not stable where the
penalty is, or its position error larger beyond the noise); against it when it costs no more than
MUCH times and is as accurate (within the noise) or more; a comparison whose penalty run is not
stable is not judged.
"""

import math

from .. import reader, rules
from .common import SCENE_ORDER, Verdict, floor_mm, scene_cell, tally_macros, verdict_line

MUCH = 2.0
NUMBERS = ["pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "t_contact_us", "t_contact_min_us",
           "t_contact_max_us", "t_step_us", "t_step_min_us", "t_step_max_us",
           "t_bound_us", "voxel_mm"]


def accuracy_rows(ctx):
    """accuracy_time.csv ([] when missing): claims (c), (d), the completed model."""
    return ctx.csv("accuracy_time.csv", NUMBERS)


def with_bound(r):
    """The restriction's row with the bound's cost added to its contact time (and its range)."""
    b = reader.num(r.get("t_bound_us"))
    out = dict(r)
    if reader.present(b):
        for k in ["t_contact_us", "t_contact_min_us", "t_contact_max_us"]:
            out[k] = reader.num(r.get(k)) + b
    return out


def outcome(proj, pen, floor):
    """'a' (for the claim), 'b' (against), or not judged; and the figures behind it."""
    gap = rules.evidence_gap(pen)
    if gap:
        return gap, None
    if not rules.is_stable(proj):
        return "a", "improper: the restriction is not stable"
    p = with_bound(proj)
    ratio = p["t_contact_us"] / pen["t_contact_us"] if pen["t_contact_us"] > 0 else math.nan
    slower = rules.time_decide(pen, p, "t_contact", factor=MUCH) == "a"
    worse = rules.decide(pen, proj, floor=floor) == "a"
    if slower or worse:
        return "a", "%s%s" % ("costs %.3gx" % ratio if slower else "", (", " if slower else "") + "less accurate" if worse else "")
    return "b", "%.3gx the time, as accurate" % ratio


def judge(ctx):
    rows = accuracy_rows(ctx)
    if not rows:
        return Verdict("c_restrictions", rules.NOT_TESTED, ["## (c) Restrictions cost much time", "",
                                                            "Not tested: results/accuracy_time.csv is missing.", ""])
    md = ["## (c) Restrictions are improper: finding the bound costs much time", "",
          "Per scenario and detector: the restriction (projection, plus the bound: CGAL's corefinement of the two "
          "surfaces on the same states) against the penalty force (k = 500 N/m) with the same detector. For the "
          "claim: over %gx the penalty's time beyond the repeats' spread, or not stable, or less accurate beyond "
          "the noise (the claim's own rule: a restriction that is not stable where the penalty is evidence is "
          "improper, so the restriction itself need not be evidence; the penalty must be). The ratio range the "
          "report quotes is over the judged pairs." % MUCH, "",
          "| scenario | detector | penalty (µs) | projection (µs) | bound (µs) | restriction / penalty | penalty err. (mm) "
          "| projection err. (mm) | outcome |", "|---|---|---:|---:|---:|---:|---:|---:|---|"]
    outcomes, bound_ratios = [], []
    for scene in SCENE_ORDER:
        floor = floor_mm(ctx, scene)
        for det, label in [("voxel", None), ("hash", "hash"), ("cgal", "cgal"), ("fcl", "fcl")]:
            g = [r for r in rows if r["scene"] == scene and r["detector"] == det and r.get("two_sided") != "yes"]
            proj = [r for r in g if r["eliminator"] == "projection"]
            pen = [r for r in g if r["eliminator"] == "line" and r["force"] == "k=500"]
            for p in proj:
                q = next((r for r in pen if r["config"] == p["config"]), None)
                if q is None:
                    continue
                o, why = outcome(p, q, floor)
                outcomes.append(o)
                b = reader.num(p.get("t_bound_us"))
                wb = with_bound(p)
                if reader.present(b) and q["t_contact_us"] > 0 and o in ("a", "b"):  # the judged pairs'
                    bound_ratios.append(wb["t_contact_us"] / q["t_contact_us"])
                md.append("| %s | %s | %.3g | %.3g | %s | %s | %.3g | %.3g | %s |" % (
                    scene_cell(ctx, scene), p["config"], q["t_contact_us"], p["t_contact_us"], "%.3g" % b if reader.present(b) else "-",
                    "%.3g" % (wb["t_contact_us"] / q["t_contact_us"]) if q["t_contact_us"] > 0 else "-",
                    q["pos_err_max_mm"], p["pos_err_max_mm"],
                    {"a": "for (%s)" % why, "b": "against (%s)" % why}.get(o, "not judged (penalty: %s)" % o)))
    verdict = rules.claim_verdict(outcomes, "a")
    md += ["", verdict_line("(c)", verdict, outcomes), ""]
    macros = tally_macros("ClaimC", verdict, outcomes) + [("ClaimCMuch", "%g" % MUCH)]
    macros += [("ClaimCRatioMin", "%.0f" % min(bound_ratios) if bound_ratios else "--"),
               ("ClaimCRatioMax", "%.0f" % max(bound_ratios) if bound_ratios else "--")]
    return Verdict("c_restrictions", verdict, md, macros, data=outcomes)
