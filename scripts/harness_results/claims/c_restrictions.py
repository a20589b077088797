"""Claim (c), section 2: "All methods based on restrictions are improper for this case because
collision joint bound calculation is hard and costs much time." A restriction computes the bound of
the region the two bodies share and moves the points out of it.

The verdict (ClaimC) comes from a bound as a practitioner computes it (results/restriction.csv,
`scripts/study.py restriction`): the `volume` eliminator, the shared volume and its gradient by
layered depth images (Faure et al. 2008, the paper's own reference for voxel-based penetration) and
one mass-weighted Newton step; per scene and detector against the penalty force (k = 500 N/m along
the line) with the same detector, every response timed under one protocol (the timing runs do the
same work, one at a time). A comparison goes for the claim when the restriction costs much time (its
mean time per step over MUCH times the penalty's, the repeats' ranges of the means disjoint) or is
improper (not stable, tunnelling or no better than no contact force where the penalty is evidence,
or its position error larger beyond the noise); against it when it costs at most MUCH times and is
as accurate (within the noise) or more; over MUCH times within the repeats' spread is within the
noise; a comparison whose penalty run is not evidence is not judged. Its own thresholds are varied
(OWN_VARIANTS: the factor 1.5, 2, 3; the mean, the 99th percentile or the median per step; judged on
time or improper, or on the time alone, the claim's reason): a
verdict that they change is stated fragile.

Shown beside, not judging: projection without a bound (what the restriction costs without it) and
projection with the exact bound (CGAL's corefinement of the two surfaces on the same states, timed
apart: t_bound_us), the slowest bound there is. It makes a second, named finding (ClaimCExact) by
the same rule; without restriction.csv it is judged on accuracy_time.csv as the study before it did.
"""

from .. import reader, rules
from .common import SCENE_ORDER, Verdict, exception_record, figure, floor_mm, scene_cell, tally_macros, verdict_line

MUCH = 2.0
# The claim's own thresholds, varied: (factor, time statistic); the first is the test as written.
OWN_VARIANTS = [(f, st, b) for b in ("time or improper", "time alone") for st in ("mean", "p99", "median")
                for f in (MUCH, 1.5, 3.0)]
STAT_KEY = {"mean": "t_contact_mean", "p99": "t_contact_p99", "median": "t_contact"}
# The volume restriction's own time: its response part alone (the layered depth images and the Newton
# step); it uses no contact the pair's detector finds, so the detection it runs beside is not its cost.
OWN_PART_KEY = {"mean": "t_eliminate_mean", "p99": "t_eliminate_p99", "median": "t_eliminate_median"}
NUMBERS = ["pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "t_contact_us", "t_contact_min_us",
           "t_contact_max_us", "t_step_us", "t_step_min_us", "t_step_max_us",
           "t_bound_us", "voxel_mm"]


RESTRICTION_NUMBERS = ["pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "tunnelled", "steps",
                       "t_eliminate_mean_us", "t_eliminate_mean_min_us", "t_eliminate_mean_max_us",
                       "t_eliminate_p99_us", "t_eliminate_p99_min_us", "t_eliminate_p99_max_us",
                       "t_eliminate_median_us", "t_eliminate_median_min_us", "t_eliminate_median_max_us",
                       "t_contact_us", "t_contact_min_us", "t_contact_max_us", "t_contact_mean_us",
                       "t_contact_mean_min_us", "t_contact_mean_max_us", "t_contact_p99_us", "t_contact_p99_min_us",
                       "t_contact_p99_max_us", "t_bound_us", "voxel_mm", "contact_power_ratio"]


def restriction_rows(ctx):
    """restriction.csv ([] when missing): the practical bound's study."""
    return ctx.csv("restriction.csv", RESTRICTION_NUMBERS)


def accuracy_rows(ctx):
    """accuracy_time.csv ([] when missing): claims (c), (d), the completed model."""
    return ctx.csv("accuracy_time.csv", NUMBERS)


def timed(r, stat="median", bound=0.0):
    """The row's time per step under `stat` (mean, p99, median) as time_decide reads it (key
    "t": t_us, t_min_us, t_max_us: the repeats' range of that statistic), the bound's µs added; NaN
    where the row lacks it (a study file before the mean and p99). A volume restriction's row: its
    response part alone (OWN_PART_KEY) where the file has it."""
    k = STAT_KEY[stat]
    if r.get("eliminator") == "volume" and reader.present(reader.num(r.get(OWN_PART_KEY[stat] + "_us"))):
        k = OWN_PART_KEY[stat]
    v = reader.num(r.get(k + "_us"))
    b = bound if reader.present(bound) else 0.0
    return {"t_us": v + b, "t_min_us": reader.num(r.get(k + "_min_us"), v) + b,
            "t_max_us": reader.num(r.get(k + "_max_us"), v) + b}


def outcome(rest, pen, floor, factor=MUCH, stat="median", bound=0.0, basis="time or improper"):
    """'a' (for the claim), 'b' (against), WITHIN_NOISE, or why it is not judged; and the words
    behind it. rest: the restriction's row (its bound's µs `bound` added to its time), pen: the
    penalty's with the same detector. basis "time alone" (an own-threshold variant): judged on the
    time only, the restriction's stability and accuracy set aside (the claim's reason is the time)."""
    gap = rules.evidence_gap(pen)
    if gap:
        return gap, None
    tr, tp = timed(rest, stat, bound), timed(pen, stat)
    if not (reader.present(tr["t_us"]) and reader.present(tp["t_us"])) or tp["t_us"] <= 0:
        return rules.MISSING, None
    ratio = tr["t_us"] / tp["t_us"]
    slower = rules.time_decide(tp, tr, "t", factor=factor) == "a"
    rgap = rules.evidence_gap(rest)
    improper = None
    if basis != "time alone":
        if rgap == rules.NOT_STABLE:
            improper = "improper: %s" % (rest.get("stability") or rules.NOT_STABLE)
        elif rgap is not None:
            improper = "improper: %s" % rgap
        elif rules.decide(pen, rest, floor=floor) == "a":
            improper = "less accurate"
    if slower or improper:
        return "a", ", ".join(w for w in ("costs %.3gx" % ratio if slower else "", improper or "") if w)
    if ratio <= factor:
        return "b", "%.3gx the time%s" % (ratio, ", as accurate" if basis != "time alone" else "")
    return rules.WITHIN_NOISE, "%.3gx the time, within the repeats' spread of %gx" % (ratio, factor)


def general_outcome(rest, pen, o):
    """`o` (outcome of the pair) under the general evidence rule: not judged, with why, where the
    restriction is not evidence (the claim's own rule counts it improper: for)."""
    gap = rules.evidence_gap(rest)
    return o if gap is None or o not in ("a", "b", rules.WITHIN_NOISE) else gap


EXCEPTION = ("restriction runs that are not evidence (not stable, tunnelling or no better than no force), counted "
             "improper by (c)'s own rule where the general rule does not judge a pair with a run that is not evidence")


def ratio_text(r, pen, stat, bound=0.0):
    """Its time over the penalty's, marked where the run failed (its times are over the steps it ran,
    not the same work)."""
    a, b = timed(r, stat, bound)["t_us"], timed(pen, stat)["t_us"]
    if not (reader.present(a) and reader.present(b) and b > 0):
        return "-"
    failed = r.get("stability") == "failed" or r.get("status") == "failed"
    return "%.3g%s" % (a / b, " (failed at step %d)" % int(reader.num(r.get("steps"), 0)) if failed else "")


def pairs_of(rows, scene):
    """[(detector label, penalty row, volume row, projection row, projection + exact bound row)] of
    restriction.csv on `scene` (None where a row is missing)."""
    out = []
    for label in dict.fromkeys(r["config"] for r in rows if r["scene"] == scene and r["config"] != rules.NO_FORCE):
        g = [r for r in rows if r["scene"] == scene and r["config"] == label]
        pick = lambda resp: next((r for r in g if r.get("response") == resp), None)  # noqa: E731
        out.append((label, pick("penalty"), pick("volume (LDI bound)"), pick("projection"),
                    pick("projection + exact bound")))
    return out


def judge_practical(ctx, rows):
    """ClaimC (the practical bound) and ClaimCExact (projection with CGAL's corefinement) from
    restriction.csv: (md, macros, outcomes, own text or None)."""
    md = ["## (c) Restrictions are improper: finding the bound costs much time", "",
          "results/restriction.csv (`scripts/study.py restriction`): per scenario and detector, the restriction with "
          "a practical bound (`volume`: the volume the bodies share and its gradient by layered depth images, as "
          "Faure et al. 2008 compute it, and one mass-weighted Newton step; its time is that part alone, bound "
          "included: it uses no contact the pair's detector finds, so the detection run beside it is not its cost) "
          "against the penalty force (k = 500 N/m) with the same detector (detection and response), both timed by the "
          "same protocol (timing runs of the "
          "same work, one at a time; the pooled mean per step, the 99th percentile beside). For the claim: over %gx "
          "the penalty's mean time beyond the repeats' spread, or improper (not stable, tunnelling or no better than "
          "no contact force where the penalty is evidence, or less accurate beyond the noise); against: at most %gx "
          "and as accurate; over %gx within the spread: within the noise. Beside it, not judging: projection without "
          "a bound and projection with the exact bound (CGAL's corefinement of the two surfaces on the same states), "
          "the slowest bound there is. The volume response moves both bodies (it is two-sided), the penalty only "
          "the guest: both are measured against the two-sided reference." % (MUCH, MUCH, MUCH), "",
          "| scenario | detector | penalty mean (p99) µs | volume / penalty, mean (p99) | projection / penalty | "
          "projection + exact bound / penalty | penalty err. (mm) | volume err. (mm) | projection err. (mm) | outcome |",
          "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    outcomes, exact, ratios, exact_ratios, items, labels = [], [], [], [], [], []
    general, general_exact = [], []
    for scene in SCENE_ORDER + sorted({r["scene"] for r in rows} - set(SCENE_ORDER)):
        floor = floor_mm(ctx, scene)
        for label, pen, vol, proj, pb in pairs_of(rows, scene):
            if pen is None or vol is None:
                continue
            items.append((pen, vol, floor))
            o, why = outcome(vol, pen, floor, MUCH, "mean")
            outcomes.append(o)
            general.append(general_outcome(vol, pen, o))
            labels.append(pen.get("detector") or label)
            if pb is not None:
                oe, _ = outcome(pb, pen, floor, MUCH, "mean", reader.num(pb.get("t_bound_us")))
                exact.append(oe)
                general_exact.append(general_outcome(pb, pen, oe))
                if oe in ("a", "b", rules.WITHIN_NOISE):
                    exact_ratios.append(timed(pb, "mean", reader.num(pb.get("t_bound_us")))["t_us"] /
                                        timed(pen, "mean")["t_us"])
            if o in ("a", "b", rules.WITHIN_NOISE):
                ratios.append(timed(vol, "mean")["t_us"] / timed(pen, "mean")["t_us"])
            md.append("| %s | %s | %.3g (%.3g) | %s (%s) | %s | %s | %s | %s | %s | %s |" % (
                scene_cell(ctx, scene), label, reader.num(pen.get("t_contact_mean_us")),
                reader.num(pen.get("t_contact_p99_us")), ratio_text(vol, pen, "mean"), ratio_text(vol, pen, "p99"),
                ratio_text(proj, pen, "mean") if proj else "-",
                ratio_text(pb, pen, "mean", reader.num(pb.get("t_bound_us"))) if pb else "-",
                figure(pen), figure(vol), figure(proj) if proj else "-",
                {"a": "for (%s)" % why, "b": "against (%s)" % why,
                 rules.WITHIN_NOISE: "within the noise (%s)" % why}.get(o, "not judged (penalty: %s)" % o)))
    verdict = rules.claim_verdict(outcomes, "a")
    own = {}
    for f, st, b in OWN_VARIANTS:
        own.setdefault(rules.claim_verdict([outcome(v, p, fl, f, st, 0.0, b)[0] for p, v, fl in items], "a"),
                       []).append((f, st, b))
    agree = len(own.get(verdict, []))
    flips = ["%s under %d: %s" % (vv, len(vs), ", ".join("(x%g, %s, %s)" % v for v in vs)) for vv, vs in own.items()
             if vv != verdict]
    own_text = ("robust over its own thresholds: %d of %d (factor 1.5, 2, 3; the mean, the 99th percentile or the "
                "median per step; judged on time or improper, or on the time alone)" % (agree, len(OWN_VARIANTS))
                if not flips else
                "fragile over its own thresholds: %d of %d agree; %s" % (agree, len(OWN_VARIANTS), "; ".join(flips)))
    everdict = rules.claim_verdict(exact, "a")
    dets = sorted({lab for (lab, o) in zip(labels, outcomes) if o in ("a", "b", rules.WITHIN_NOISE)})
    n_dec = sum(1 for o in outcomes if o in ("a", "b", rules.WITHIN_NOISE))
    basis = ("Its %d comparisons decisive by its own rule use %s's detection%s%s." % (
        n_dec, " and ".join(dets) if dets else "no", " only" if len(dets) == 1 else "",
        (": the rule's minimum (%d), one fewer and it would be inconclusive; the paper's grid's penalty runs are "
         "not evidence in any scene" % rules.MIN_DECISIVE) if n_dec == rules.MIN_DECISIVE else "")) if outcomes else ""
    caveat = ("The bound is this harness's CPU implementation on one thread (every triangle of both bodies "
              "rasterised along three axes at a pixel of half the smaller mean edge, one Newton step per step); "
              "Faure et al. rasterise on a GPU, where its cost differs: the verdict is about this implementation on "
              "this machine, and its \"improper\" outcomes (unstable, tunnelling) about this restriction, not every "
              "restriction.")
    md += ["", verdict_line("(c)", verdict, outcomes), "", basis, "", caveat, "",
           "**The claim's own thresholds:** %s." % own_text, "",
           "The restriction with its practical bound takes %s times the penalty's mean time in the comparisons made. "
           "The exact bound (projection with CGAL's corefinement), a second finding by the same rule: %s (%s); it "
           "takes %s times the penalty's time." % (
               rng(ratios), everdict, rules.tally_text(rules.tally(exact, "a")), rng(exact_ratios)), ""]
    macros = tally_macros("ClaimC", verdict, outcomes) + tally_macros("ClaimCExact", everdict, exact)
    macros += [("ClaimCMuch", "%g" % MUCH), ("ClaimCRatioMin", num(min(ratios)) if ratios else "--"),
               ("ClaimCRatioMax", num(max(ratios)) if ratios else "--"),
               ("ClaimCExactRatioMin", num(min(exact_ratios)) if exact_ratios else "--"),
               ("ClaimCExactRatioMax", num(max(exact_ratios)) if exact_ratios else "--"), ("ClaimCOwn", own_text),
               ("ClaimCBasis", basis)]
    rests = {p: t for p, t in (("ClaimC", exception_record(outcomes, general, EXCEPTION)),
                               ("ClaimCExact", exception_record(exact, general_exact, EXCEPTION))) if t}
    for p, t in rests.items():
        md += ["**The claim's own rule (%s):** %s." % ("as stated" if p == "ClaimC" else "the exact bound", t["text"]), ""]
    return md, macros, outcomes + exact, (own_text if flips else None), rests


def num(x):
    """Two significant digits without an exponent."""
    return "%.2g" % x if abs(x) < 100 else "%d" % int(float("%.2g" % x))


def rng(xs):
    xs = [x for x in xs if reader.present(x)]
    return "%s to %s" % (num(min(xs)), num(max(xs))) if xs else "--"


def judge(ctx):
    rows = restriction_rows(ctx)
    if rows:
        md, macros, outcomes, own, rests = judge_practical(ctx, rows)
        return Verdict("c_restrictions", dict(macros)["ClaimCVerdict"], md, macros, data=outcomes,
                       own={"ClaimC": own} if own else None, rests=rests)
    verdict, md, macros, outcomes = judge_exact_accuracy(ctx)
    md = md + ["The practical bound (`scripts/study.py restriction`, results/restriction.csv) was not run: (c) is "
               "not tested, the exact bound above is its second finding.", ""]
    macros = tally_macros("ClaimC", rules.NOT_TESTED, []) + [
        (n if n == "ClaimCMuch" else n.replace("ClaimC", "ClaimCExact", 1), v) for n, v in macros]
    return Verdict("c_restrictions", rules.NOT_TESTED, md, macros, data=outcomes)


def judge_exact_accuracy(ctx):
    """The exact bound on accuracy_time.csv (before the restriction study): (verdict, md, macros, outcomes)."""
    rows = accuracy_rows(ctx)
    if not rows:
        return (rules.NOT_TESTED, ["## (c) Restrictions cost much time", "",
                                   "Not tested: results/accuracy_time.csv is missing.", ""],
                [("ClaimCVerdict", rules.NOT_TESTED)], [])
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
        floor = floor_mm(ctx, scene, of_kind=True)
        for det, label in [("voxel", None), ("hash", "hash"), ("cgal", "cgal"), ("fcl", "fcl")]:
            g = [r for r in rows if r["scene"] == scene and r["detector"] == det and r.get("two_sided") != "yes"]
            proj = [r for r in g if r["eliminator"] == "projection"]
            pen = [r for r in g if r["eliminator"] == "line" and r["force"] == "k=500"]
            for p in proj:
                q = next((r for r in pen if r["config"] == p["config"]), None)
                if q is None:
                    continue
                b = reader.num(p.get("t_bound_us"))
                o, why = outcome(p, q, floor, MUCH, "median", b)
                outcomes.append(o)
                with_b = timed(p, "median", b)["t_us"]
                if reader.present(b) and q["t_contact_us"] > 0 and o in ("a", "b"):  # the judged pairs'
                    bound_ratios.append(with_b / q["t_contact_us"])
                md.append("| %s | %s | %.3g | %.3g | %s | %s | %.3g | %.3g | %s |" % (
                    scene_cell(ctx, scene, of_kind=True), p["config"], q["t_contact_us"], p["t_contact_us"], "%.3g" % b if reader.present(b) else "-",
                    "%.3g" % (with_b / q["t_contact_us"]) if q["t_contact_us"] > 0 else "-",
                    q["pos_err_max_mm"], p["pos_err_max_mm"],
                    {"a": "for (%s)" % why, "b": "against (%s)" % why,
                     rules.WITHIN_NOISE: "within the noise (%s)" % why}.get(o, "not judged (penalty: %s)" % o)))
    verdict = rules.claim_verdict(outcomes, "a")
    md += ["", verdict_line("(c)", verdict, outcomes), ""]
    macros = tally_macros("ClaimC", verdict, outcomes) + [("ClaimCMuch", "%g" % MUCH)]
    macros += [("ClaimCRatioMin", "%.0f" % min(bound_ratios) if bound_ratios else "--"),
               ("ClaimCRatioMax", "%.0f" % max(bound_ratios) if bound_ratios else "--")]
    return verdict, md, macros, outcomes
