"""Real time (the paper's aim: collision handling for a real-time simulator), on results/realtime.csv
(scripts/study.py realtime), split in two:
  collision unit   the paper's voxel model's detection and elimination per step, at the scene's dt
                   on one thread, against a haptic budget of 1 ms per step: for the claim when it
                   is under the budget;
  simulator        the whole step: for the claim in a scene when some stable run of a method whose
                   error is within ACCURATE times the best exact method's runs at a real-time factor
                   of at least 1 (simulated time per wall time; any dt mode, one or two threads);
                   against it otherwise.
"""

import math

from .. import rules
from .common import SCENE_ORDER, Verdict, tally_macros, verdict_line

BUDGET_US = 1000.0
ACCURATE = 1.5
NUMBERS = ["t_step_us", "t_contact_us", "realtime_factor", "pos_err_max_mm", "error_over_best", "threads", "dt"]


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
    md = head + ["From results/realtime.csv (the machine: two cores; one and two threads). Collision unit: the "
                 "paper's voxel model's detection + elimination at the scene's dt on one thread, against %g µs per "
                 "step (judged only where that run is evidence: stable, helps, tunnels nothing). Simulator: the fastest "
                 "run that is evidence of a method within %gx of the best exact method's error, "
                 "real-time factor = dt / median step." % (BUDGET_US, ACCURATE), "",
                 "| scenario | collision unit (µs) | within 1 ms | fastest accurate run | step (µs) | real-time factor | "
                 "error / best exact |", "|---|---:|---|---|---:|---:|---:|"]
    unit, sim, rtf = [], [], []
    for scene in SCENE_ORDER:
        sr = [r for r in rows if r["scene"] == scene]
        if not sr:
            continue
        paper = [r for r in sr if r["kind"] == "paper" and r["mode"] == "scene dt" and r["threads"] == 1]
        u = paper[0]["t_contact_us"] if paper else math.nan
        gap = rules.evidence_gap(paper[0]) if paper else rules.MISSING
        unit.append(gap or ("a" if u < BUDGET_US else "b"))
        ok = [r for r in sr if rules.is_evidence(r) and not math.isnan(r["error_over_best"])
              and r["error_over_best"] <= ACCURATE and r["realtime_factor"] > 0]
        best = max(ok, key=lambda r: r["realtime_factor"]) if ok else None
        sim.append(("a" if best["realtime_factor"] >= 1.0 else "b") if best else rules.NOT_STABLE)
        if best:
            rtf.append(best["realtime_factor"])
        md.append("| %s | %s | %s | %s | %s | %s | %s |" % (
            scene, "%.3g" % u if paper else "-", (("yes" if u < BUDGET_US else "no") + (
                "" if not gap else " (not judged: the paper's run %s)" % (
                    paper[0].get("stability") if gap == rules.NOT_STABLE else gap))) if paper else "-",
            "%s, %s, %d thread%s" % (best["method"], best["mode"], best["threads"], "" if best["threads"] == 1 else "s")
            if best else "none stable and accurate", "%.3g" % best["t_step_us"] if best else "-",
            "%.3g" % best["realtime_factor"] if best else "-", "%.3g" % best["error_over_best"] if best else "-"))
    vu, vs = rules.claim_verdict(unit, "a"), rules.claim_verdict(sim, "a")
    md += ["", verdict_line("(real time, collision unit)", vu, unit),
           "", verdict_line("(real time, simulator)", vs, sim), ""]
    macros = tally_macros("ClaimRTUnit", vu, unit) + tally_macros("ClaimRTSim", vs, sim)
    macros += [("ClaimRTSimMin", "%.2g" % min(rtf) if rtf else "--"), ("ClaimRTSimMax", "%.2g" % max(rtf) if rtf else "--")]
    return Verdict("realtime", vs, md, macros, data=(unit, sim))
