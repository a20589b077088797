"""Claim (d), section 3: "collision search using space voxelization is one of the most fast".

As the paper states it (detection alone): results/detection.csv (study.py detection), every detector
on the same states, timed alone and scored against CGAL's exact sets. Per source (a bundled scene's
states, a bench size): the paper's voxel model is represented by its setting of highest guest recall
(of the pair's voxel size, half and twice it; the most precise among equals); the detectors of comparable
recall are the others whose guest recall is at least its recall minus RECALL_SLACK (CGAL, the truth,
always is one); the paper's model is "one of the most fast" (for) when its time is within a factor
FASTEST of the fastest of them, against when that one is faster by more than FASTEST beyond the
rounds' spread (rules.time_decide), within the noise otherwise; not judged where nothing penetrates
in the source's states (recall undefined). Precision is shown beside, not judged: the claim is about
speed, and the issue's test compares detectors of comparable recall. The claim's own thresholds
(FASTEST, RECALL_SLACK, which voxel setting represents the model) are varied in OWN_VARIANTS and the
verdict's agreement over them is stated.

The collision unit at matched error (a second finding, the test this claim had before: detection
and elimination together) is judged on results/accuracy_time.csv: per scenario, the paper's voxel
model's most accurate setting that is stable and helps (its position error at most 90 % of the run
without contact force's, or its depth with a position error no larger: rules.useful) sets the error
e_v; every method family (the paper's voxel model, the completed model voxel_exact, spatial hashing,
CGAL, FCL) is represented by its fastest stable setting whose error is at most e_v plus the noise.
The paper's model is "one of the most fast" when its time (detection and elimination, median of the
repeats) is within a factor FASTEST of the fastest family's at that error; the comparison is against
the claim when another family is faster by more than that factor beyond the spread of the repeats,
and not judged when the paper's model has no stable setting that helps.
"""

import math
import os

from .. import reader, rules
from .c_restrictions import accuracy_rows
from .common import NO_FORCE, SCENE_ORDER, Verdict, floor_mm, scene_cell, tally_macros, verdict_line

FASTEST = 2.0
RECALL_SLACK = 0.05
# The claim's own thresholds, varied: (factor, recall slack, the paper's setting: "best" recall or
# the pair's own voxel size). The first is the test as written.
OWN_VARIANTS = [(f, sl, st, t) for t in ("detect", "detect_warm") for st in ("best", "own")
                for sl in (RECALL_SLACK, 0.0, 0.10) for f in (FASTEST, 1.5, 3.0)]
DETECTION_TEXT = ["source", "kind", "pair", "detector", "setting", "device", "machine"]
FAMILIES = [("voxel", "the paper's voxel model"), ("voxel_exact", "voxel_exact (completed)"), ("hash", "hashing"),
            ("cgal", "CGAL"), ("fcl", "FCL")]


def paper_rows(rows, scene):
    return [r for r in rows if r["scene"] == scene and r["detector"] == "voxel" and r["config"] != NO_FORCE]


def detection_sources(rows):
    """[(source, [rows of its first pair])] in the file's order."""
    out = {}
    for r in rows:
        first = out.setdefault(r["source"], {"pair": r["pair"], "rows": []})
        if r["pair"] == first["pair"]:
            first["rows"].append(r)
    return [(k, v["rows"]) for k, v in out.items()]


def detection_outcome(rows, factor=FASTEST, slack=RECALL_SLACK, setting="best", timing="detect"):
    """(outcome, the paper's row, the fastest comparable row) of one source; `timing` the time
    compared: "detect" (each call after the other detectors: cold) or "detect_warm" (repeated)."""
    key = timing + "_us"
    vox = [r for r in rows if r["detector"] == "voxel" and reader.present(r.get(key))]
    if not vox or not reader.num(rows[0].get("true_pen_guest"), 0) > 0:
        return rules.MISSING, None, None
    if setting == "own":
        mine = vox[0]  # the pair's own voxel size: the first voxel row
    else:
        # highest recall; among equals the higher precision (a quality, not the timing's noise)
        mine = min(vox, key=lambda r: (-reader.num(r["recall"], 0.0), -reader.num(r.get("precision"), 0.0)))
    floor = reader.num(mine["recall"], 0.0) - slack
    comparable = [r for r in rows if r["detector"] != "voxel" and reader.present(r.get(key))
                  and reader.num(r.get("recall"), 0.0) >= floor - 1e-12]
    if not comparable:
        return "a", mine, None
    f = min(comparable, key=lambda r: r[key])
    if rules.time_decide(f, mine, timing, factor=factor) == "a":
        return "b", mine, f
    if mine[key] <= factor * f[key]:
        return "a", mine, f
    return rules.WITHIN_NOISE, mine, f


def cell(r):
    if r is None:
        return "-"
    return "%.3g (%s) µs; R %s / %s; P %s" % (r["detect_us"], fmt(r.get("detect_warm_us")), fmt(r.get("recall")),
                                              fmt(r.get("recall_host")), fmt(r.get("precision")))


def fmt(v):
    v = reader.num(v)
    return "-" if math.isnan(v) else "%.3g" % v


def judge_detection(ctx):
    """(outcomes, md lines, macros) of the claim as stated, from detection.csv."""
    rows = reader.read_csv(os.path.join(ctx.root, "detection.csv"), text=DETECTION_TEXT, missing=[])
    title = ["## (d) Voxelization is one of the fastest searches: detection alone, as stated", ""]
    if not rows:
        return None, title + ["Not tested: results/detection.csv is missing (scripts/study.py detection).", ""], [], None
    sources = detection_sources(rows)
    md = title + [
        "results/detection.csv (`scripts/study.py detection`): every detector on the same states (a scene's run "
        "as written, %d states over its steps; a bench scene's initial state), one-sided detection timed alone "
        "(one thread, µs per state, median over rounds in which the detectors take turns), two-sided reports "
        "scored node by node against CGAL's exact sets, summed over the states. The paper's model: its setting "
        "of highest guest recall among the pair's voxel size, half and twice it (the most precise among equals); "
        "comparable recall: guest recall "
        "at least its own minus %g; it is one of the fastest when within %gx of the fastest detector of "
        "comparable recall (against when that one is faster by more, beyond the rounds' spread). Cells: time "
        "(warm: the same state again at once); recall guest / host; precision guest. Machine: %s." % (
            int(max(reader.num(r.get("states"), 1) for r in rows)), RECALL_SLACK, FASTEST, rows[0].get("machine", "-")),
        "", "| source | the paper's model (setting) | voxel_exact | hash | fcl | cgal | fastest comparable | outcome |",
        "|---|---|---|---|---|---|---|---|"]
    outcomes, speed, prec, price, cg_cold, cg_warm, host, ve_low = [], [], [], [], [], [], [], []
    for source, rs in sources:
        o, mine, f = detection_outcome(rs)
        outcomes.append(o)
        by = {r["detector"]: r for r in rs if r["detector"] != "voxel"}
        word = {"a": "for", "b": "against", rules.WITHIN_NOISE: "within the noise"}.get(o, "not judged (nothing penetrates)")
        if mine is not None and f is not None:
            speed.append(f["detect_us"] / mine["detect_us"])
            word += " (%.3gx)" % (f["detect_us"] / mine["detect_us"])
        if mine is not None:
            prec.append(reader.num(mine.get("precision")))
            host.append(reader.num(mine.get("recall_host")))
            if "voxel_exact" in by and reader.num(by["voxel_exact"].get("recall"), 1.0) < 0.99:
                ve_low.append("%s (%.3g)" % (source, reader.num(by["voxel_exact"]["recall"])))
            if "voxel_exact" in by:
                price.append(by["voxel_exact"]["detect_us"] / mine["detect_us"])
            if "cgal" in by:
                cg_cold.append(by["cgal"]["detect_us"] / mine["detect_us"])
                cg_warm.append(reader.num(by["cgal"].get("detect_warm_us")) / reader.num(mine.get("detect_warm_us")))
        md.append("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
            source, "%s (%s)" % (cell(mine), mine["setting"]) if mine else "-", cell(by.get("voxel_exact")),
            cell(by.get("hash")), cell(by.get("fcl")), cell(by.get("cgal")), f["detector"] if f else "-", word))
    verdict = rules.claim_verdict(outcomes, "a")
    scene_only = [o for (src, rs), o in zip(sources, outcomes) if rs and rs[0].get("kind") == "scene"]
    own = {}
    for v in OWN_VARIANTS:
        own.setdefault(rules.claim_verdict([detection_outcome(rs, *v)[0] for _s, rs in sources], "a"), []).append(v)
    agree = len(own.get(verdict, []))
    flips = ["%s under %d: %s" % (vv, len(vs), ", ".join("(x%g, slack %g, %s, %s)" % v for v in vs[:3]) +
                                  (" ..." if len(vs) > 3 else "")) for vv, vs in own.items() if vv != verdict]
    own_text = ("robust over its own thresholds: %d of %d (factor 1.5, 2, 3; recall slack 0, 0.05, 0.1; the "
                "setting of best recall or the pair's own; cold or warm times)" % (agree, len(OWN_VARIANTS)) if not flips else
                "fragile over its own thresholds: %d of %d agree; %s" % (agree, len(OWN_VARIANTS), "; ".join(flips)))
    prec = [p for p in prec if not math.isnan(p)]
    md += ["", "The fastest detector of comparable recall takes %s times the paper's model's time. Precision is not "
           "judged but is the price of this speed: the paper's model reports nodes that do not penetrate (guest "
           "precision %s to %s), and with the line or plane response each is pushed. The grid with an exact narrow "
           "phase (voxel_exact) reports none falsely and takes %s times the paper's model's time." % (
               rng(speed), "%.3g" % min(prec) if prec else "-", "%.3g" % max(prec) if prec else "-", rng(price)), "",
           "FCL reports the vertices of intersecting triangles, so only surface nodes, while the truth counts every "
           "node inside (interior nodes too): its low recall on the bench states is by construction, not a "
           "failure to find the surfaces' contact. Times: the first call on a state comes after the other detectors "
           "ran (cold caches, seeds from another state), the warm one repeats it at once; a run's step lies "
           "between (`timing_us.detect` of a run's summary). CGAL gains most from warmth (its closest-face seeds): "
           "cold %s, warm %s times the paper's model's." % (rng(cg_cold), rng(cg_warm)), "",
           "The paper's model is one-sided: the host nodes inside the guest are found only where its own grid, "
           "the other way round, lists guest vertices near them (host recall %s at its chosen settings). "
           "voxel_exact misses penetrating guest nodes beyond its band at %s: its recall there is not what "
           "a completed model promises, noted and not fixed here." % (rng(host), ", ".join(ve_low) or "no source"), "",
           "The bench sizes are one generated state at four sizes (a cylinder shell pressed into a layer, not "
           "deformed); on the bundled scenes alone the verdict is %s (%s)." % (
               rules.claim_verdict(scene_only, "a"), rules.tally_text(rules.tally(scene_only, "a"))), "",
           verdict_line("(d), detection alone, at comparable recall (precision not matched)", verdict, outcomes), "",
           "**The claim's own thresholds:** %s." % own_text, ""]
    macros = tally_macros("ClaimD", verdict, outcomes) + [
        ("ClaimDFactor", "%g" % FASTEST), ("ClaimDSlack", "%g" % RECALL_SLACK), ("ClaimDSpeedup", rng(speed)),
        ("ClaimDPrecision", "%s to %s" % ("%.2g" % min(prec), "%.2g" % max(prec)) if prec else "--"),
        ("ClaimDPricePrecision", rng(price)), ("ClaimDOwn", own_text), ("ClaimDHostRecall", rng(host)),
        ("ClaimDExactLow", ", ".join(ve_low).replace("_", "\\_") or "none")]
    return verdict, md, macros, (own_text if flips else None)


def num_text(x):
    """Two significant digits, without an exponent (143 as 140, not 1.4e+02)."""
    return "%.2g" % x if abs(x) < 100 else "%d" % int(float("%.2g" % x))


def rng(xs):
    xs = [x for x in xs if not math.isnan(x)]
    return "%s to %s" % (num_text(min(xs)), num_text(max(xs))) if xs else "--"


def judge(ctx):
    verdict, md, macros, own = judge_detection(ctx)
    uverdict, umd, umacros, uoutcomes = judge_unit(ctx)
    if verdict is None:
        verdict = rules.NOT_TESTED
        macros = [("ClaimDVerdict", rules.NOT_TESTED)]
    return Verdict("d_voxel_speed", verdict, md + umd, macros + umacros, data=uoutcomes, own={"ClaimD": own} if own else None,
                   rule_free=["ClaimD"])


def judge_unit(ctx):
    """The collision unit (detection + elimination) at matched error: the second finding."""
    rows = accuracy_rows(ctx)
    if not rows:
        return rules.NOT_TESTED, ["### The collision unit at matched error (a second finding)", "",
                                  "Not tested: results/accuracy_time.csv is missing.", ""], \
            [("ClaimDUnitVerdict", rules.NOT_TESTED)], []
    md = ["### The collision unit at matched error (a second finding): detection and elimination", "",
          "Per scenario: e_v = the position error of the paper's model's most accurate stable setting that helps "
          "(beats the run without contact force by 10 %%); each family's fastest stable setting with an error at "
          "most e_v plus the noise; the paper's model is one of the fastest within a factor %g of the fastest "
          "family (detection + elimination, median of the repeats, beyond their spread)." % FASTEST, ""]
    outcomes = []
    for scene in SCENE_ORDER:
        floor = floor_mm(ctx, scene, of_kind=True)
        sr = [r for r in rows if r["scene"] == scene]
        base = next((r for r in sr if r["config"] == NO_FORCE), None)
        # evidence: stable, tunnels nothing, and helps (marked against `base` by the context)
        vox = [r for r in paper_rows(rows, scene) if rules.is_evidence(r) and not math.isnan(r["pos_err_max_mm"])]
        md.append("#### %s" % scene_cell(ctx, scene, of_kind=True))
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
    md += [verdict_line("(d), the collision unit", verdict, outcomes), ""]
    return verdict, md, tally_macros("ClaimDUnit", verdict, outcomes), outcomes
