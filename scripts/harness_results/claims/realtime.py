"""Real time (the paper's aim: collision handling for a real-time simulator), on results/realtime.csv
(scripts/study.py realtime), split in two, each judged on the mean and on the 99th percentile of the
steps (a real-time step must meet its budget on most steps, not on the median one):
  collision unit   the paper's voxel model's detection and elimination per step, at the scene's dt
                   on one thread, against the budget of one step, the scene's dt (the 1 ms haptic
                   line beside): for the claim when its mean and its p99 are within the budget,
                   against it when its mean is not, within the noise when only the p99 is over;
  simulator        the whole step: in a scene, the stable run that is evidence of a method whose
                   error is within ACCURATE times the best exact method's with the largest
                   real-time factor on the mean (simulated time per wall time; any dt mode, one or
                   two threads): for the claim when its factors on the mean and on the p99 are at
                   least 1, against it when the mean's is below 1, within the noise when only the
                   p99's is. Rows without the mean and p99 (a realtime.csv from before the
                   protocol) are judged on the median, said so.
"""

import math

from .. import rules
from .common import SCENE_ORDER, Verdict, scene_cell, tally_macros, verdict_line

HAPTIC_US = 1000.0
ACCURATE = 1.5
NUMBERS = ["t_step_us", "t_contact_us", "realtime_factor", "pos_err_max_mm", "error_over_best", "threads", "dt",
           "t_step_mean_us", "t_step_p99_us", "t_contact_mean_us", "t_contact_p99_us", "budget_us",
           "realtime_factor_mean", "realtime_factor_p99"]


def pick(r, key, fallback):
    """r[key], or r[fallback] where the row does not have it (NaN or missing)."""
    v = r.get(key, math.nan)
    return r[fallback] if v is None or (isinstance(v, float) and math.isnan(v)) else v


def two_sided(mean_ok, p99_ok):
    """The outcome on the mean and the p99: both meet it "a", the mean misses it "b", else noise."""
    return "a" if mean_ok and p99_ok else "b" if not mean_ok else rules.WITHIN_NOISE


def untested_macros():
    """The macros of judge() when there is nothing to judge: the report still builds."""
    return (tally_macros("ClaimRTUnit", rules.NOT_TESTED, []) + tally_macros("ClaimRTSim", rules.NOT_TESTED, []) +
            [("ClaimRTSimMin", "--"), ("ClaimRTSimMax", "--")])


def judge(ctx):
    rows = ctx.csv("realtime.csv", NUMBERS)
    head = ["## Real time: the collision unit and the simulator", ""]
    if not rows:
        return Verdict("realtime", rules.NOT_TESTED, head + ["Not tested: results/realtime.csv is missing.", ""],
                       untested_macros())
    if "kind" not in rows[0]:
        return Verdict("realtime", rules.NOT_TESTED, head + ["Not tested: results/realtime.csv predates its method "
                                                             "and mode columns (rerun scripts/study.py realtime).", ""],
                       untested_macros())
    machine = sorted({r.get("machine") for r in rows if r.get("machine") and r.get("device") in (None, "", "cpu")})
    md = head + ["From results/realtime.csv (the machine, as the runs recorded it: %s; one and two threads). "
                 "Collision unit: the paper's voxel model's detection + elimination at the scene's dt on one thread, "
                 "mean and p99 per step against the budget of one step, the scene's dt (the %g µs haptic line "
                 "beside; judged only where that run is evidence: stable, helps, tunnels nothing). Simulator: the "
                 "run that is evidence of a method within %gx of the best exact method's error with the largest "
                 "real-time factor on the mean (RTF = dt / step time), its factors on the mean and the p99. For: "
                 "mean and p99 within the budget; against: the mean is not; within the noise: only the p99 is over. "
                 "Every error here is against the two-sided reference (the study measured no other): a one-sided "
                 "method's error includes its one-sidedness, which favours the methods both ways in \"within %gx of the "
                 "best exact method's error\"."
                 % (", ".join(machine) or "not recorded", HAPTIC_US, ACCURATE, ACCURATE), "",
                 "| scenario | budget = dt (µs) | collision unit mean (µs) | p99 (µs) | within dt | within 1 ms | "
                 "fastest accurate run | step mean (µs) | RTF mean | RTF p99 | error / best exact |",
                 "|---|---:|---:|---:|---|---|---|---:|---:|---:|---:|"]
    unit, sim, rtf = [], [], []
    for scene in SCENE_ORDER:
        sr = [r for r in rows if r["scene"] == scene and r.get("device") in (None, "", "cpu")]
        if not sr:
            continue
        paper = [r for r in sr if r["kind"] == "paper" and r["mode"] == "scene dt" and r["threads"] == 1]
        p = paper[0] if paper else None
        budget = pick(dict(p, dt_us=p["dt"] * 1e6), "budget_us", "dt_us") if p else math.nan
        um = pick(p, "t_contact_mean_us", "t_contact_us") if p else math.nan
        u99 = pick(p, "t_contact_p99_us", "t_contact_us") if p else math.nan
        gap = rules.evidence_gap(p) if p else rules.MISSING
        unit.append(gap or two_sided(um <= budget, u99 <= budget))
        ok = [r for r in sr if rules.is_evidence(r) and not math.isnan(r["error_over_best"])
              and r["error_over_best"] <= ACCURATE and pick(r, "realtime_factor_mean", "realtime_factor") > 0]
        best = max(ok, key=lambda r: pick(r, "realtime_factor_mean", "realtime_factor")) if ok else None
        if best:
            fm = pick(best, "realtime_factor_mean", "realtime_factor")
            f99 = pick(best, "realtime_factor_p99", "realtime_factor")
            sim.append(two_sided(fm >= 1.0, f99 >= 1.0))
            rtf.append(fm)
        else:
            sim.append(rules.NOT_STABLE)
        within = (("yes" if um <= budget else "no") + ("" if u99 <= budget else ", p99 over") + (
            "" if not gap else " (not judged: the paper's run %s)" % (
                p.get("stability") if gap == rules.NOT_STABLE else gap))) if p else "-"
        md.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            scene_cell(ctx, scene), "%.3g" % budget if p else "-", "%.3g" % um if p else "-", "%.3g" % u99 if p else "-", within,
            ("yes" if u99 <= HAPTIC_US else "no") if p else "-",
            "%s, %s, %d thread%s" % (best["method"], best["mode"], best["threads"], "" if best["threads"] == 1 else "s")
            if best else "none stable and accurate",
            "%.3g" % pick(best, "t_step_mean_us", "t_step_us") if best else "-",
            "%.3g" % pick(best, "realtime_factor_mean", "realtime_factor") if best else "-",
            "%.3g" % pick(best, "realtime_factor_p99", "realtime_factor") if best else "-",
            "%.3g" % best["error_over_best"] if best else "-"))
    vu, vs = rules.claim_verdict(unit, "a"), rules.claim_verdict(sim, "a")
    md += ["", verdict_line("(real time, collision unit)", vu, unit),
           "", verdict_line("(real time, simulator)", vs, sim), ""]
    macros = tally_macros("ClaimRTUnit", vu, unit) + tally_macros("ClaimRTSim", vs, sim)
    macros += [("ClaimRTSimMin", "%.2g" % min(rtf) if rtf else "--"), ("ClaimRTSimMax", "%.2g" % max(rtf) if rtf else "--")]
    return Verdict("realtime", vs, md, macros, data=(unit, sim))
