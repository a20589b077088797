"""Claim (e), section 3: "if voxels are built for large space area near penetrating bodies then
collisions are detected for any deformations". Judged on results/region.csv (scripts/study.py
region: five deformations a surgeon's scene produces, studies/region.py DEFORMATIONS), with
detection alone (force 0: the same deformation for every region).

A region detects everything when no truly penetrating guest node lies outside it at any measured
step (its outside peak over the run is 0), it detects at least RECALL_ALL of the penetrating guest
nodes over the run, and it does not flag everything: its precision is above PRECISION_GAIN times
that of the cheapest broad phase, flagging every guest node inside the overlap of the two bodies'
boxes (flag-overlap: the overlap region with no margin's flag-region in the same deformation's runs
at force 0, which see the same states); varied: flag-region, every guest node inside the region's
own box (a baseline that gets easier as the region grows). Note that a truly penetrating guest node
lies inside the host's box, so the full region has no penetrating node outside it by construction:
for the full region the test is recall and precision. The large regions are the grid over the host's
whole box (full) at every margin: the claim's "large space area" for a grid attached to the host
(varied: full and the boxes' overlap at every margin, as the study names them, although the overlap
with no margin is the smallest region of all; or every region holding at least the voxels of full
with no margin, although a half region so large still faces one way). One comparison per deformation: for when every large region
detects everything, against when one of them does not. A deformation tests the claim only
when penetrating guest nodes do leave the half region (its outside peak above zero); one that does
not is shown and not judged. With the response on (the penalty), the same figures are shown beside
with each run's stability; a deformation's large regions that are all unstable there are said so.

The claim's own thresholds (RECALL_ALL, PRECISION_GAIN, and the outside criterion: the peak over the
run or the final window's mean) are varied in OWN_VARIANTS and the verdict's agreement is stated.
"""

import math

from .. import rules
from .common import Verdict, tally_macros, verdict_line

RECALL_ALL = 0.99
# Beyond the broad phase by 5 %: the grid over the boxes' overlap differs from the box itself only
# where its voxels round the box outward (precisions equal to the 4th digit): no discrimination.
PRECISION_GAIN = 1.05
LARGE_BY_NAME = ("full", "overlap")
# The claim's own thresholds, varied: (recall, precision gain, outside criterion, what is large).
OWN_VARIANTS = [(r, g, o, l, b) for b in ("overlap", "region") for l in ("full", "names", "size")
                for o in ("peak", "window") for r in (RECALL_ALL, 0.95, 1.0) for g in (PRECISION_GAIN, 1.01, 1.5, 2.0)]
NUMBERS = ["outside_share", "outside_mean", "outside_peak", "pen_guest_mean", "recall", "precision", "precision_flag_all",
           "precision_flag_region",
           "region_voxels_mean", "region_voxels_peak", "depth_max_mm", "max_depth_peak_mm", "t_contact_us", "margin"]


def flag_overlap(det):
    """The precision of flagging every guest node inside the overlap of the two boxes: the overlap
    region with no margin's flag-region (NaN without that run)."""
    v = [r["precision_flag_region"] for r in det if r["region"] == "overlap" and r["margin"] == 0]
    return v[0] if v else math.nan


def with_baseline(det, baseline="overlap"):
    """det's rows, each with `flag` the precision its reports must beat: flag-overlap (as written) or
    its own flag-region."""
    fo = flag_overlap(det)
    return [dict(r, flag=fo if baseline == "overlap" else r["precision_flag_region"]) for r in det]


def detects_all(r, recall=RECALL_ALL, gain=PRECISION_GAIN, outside="peak"):
    out = r["outside_peak"] if outside == "peak" else r["outside_share"]
    flag = r.get("flag", r["precision_flag_region"])
    return (not math.isnan(out) and out == 0.0 and not math.isnan(r["recall"]) and r["recall"] >= recall
            and not math.isnan(r["precision"]) and not math.isnan(flag) and r["precision"] > gain * flag)


def large(det, how="full"):
    """The large regions among one deformation's runs: the full region at every margin (as written),
    by name (full and overlap at every margin) or by size (at least the voxels of full, margin 0)."""
    if how == "full":
        return [r for r in det if r["region"] == "full"]
    if how == "names":
        return [r for r in det if r["region"] in LARGE_BY_NAME]
    ref = [r["region_voxels_mean"] for r in det if r["region"] == "full" and r["margin"] == 0
           and not math.isnan(r["region_voxels_mean"])]
    if not ref:
        return [r for r in det if r["region"] == "full"]
    return [r for r in det if not math.isnan(r["region_voxels_mean"]) and r["region_voxels_mean"] >= ref[0] - 1e-9]


def why_not(r, recall=RECALL_ALL, gain=PRECISION_GAIN):
    """Why a large region does not detect everything, in words."""
    out = []
    if not r["outside_peak"] == 0.0:
        out.append("%d penetrating nodes outside it at one step" % r["outside_peak"])
    if not r["recall"] >= recall:
        out.append("recall %.3g%s" % (r["recall"], " with no penetrating node outside it (the missed ones lie in "
                                      "voxels that list no host vertex)" if r["outside_peak"] == 0.0 else ""))
    flag = r.get("flag", r["precision_flag_region"])
    if not r["precision"] > gain * flag:
        out.append("precision %.3g, not above %sthe baseline's %.3g" % (
            r["precision"], "" if gain == 1 else "%g x " % gain, flag))
    return "; ".join(out) or "-"


def deformations(rows):
    """[(deformation, its rows)] in the file's order (a file without the column: one, named by its scene)."""
    out = {}
    for r in rows:
        out.setdefault(r.get("deformation") or r["scene"], []).append(r)
    return list(out.items())


def exercised(det, outside="peak"):
    key = "outside_peak" if outside == "peak" else "outside_share"
    half = [r[key] for r in det if r["region"] == "half" and not math.isnan(r[key])]
    return bool(half) and max(half) > 0


def outcome(det, recall=RECALL_ALL, gain=PRECISION_GAIN, outside="peak", how="full", baseline="overlap"):
    """One deformation's comparison (detection alone): "a" (for), "b" (against) or MISSING (the half
    region loses nothing: the deformation does not test the claim, or no large region was run)."""
    big = large(with_baseline(det, baseline), how)
    if not big or not exercised(det, outside):
        return rules.MISSING
    return "a" if all(detects_all(r, recall, gain, outside) for r in big) else "b"


def judge(ctx):
    rows = ctx.csv("region.csv", NUMBERS)
    head = ["## (e) A large region detects collisions under any deformation", ""]
    if not rows:
        return Verdict("e_region", rules.NOT_TESTED, head + ["Not tested: results/region.csv is missing.", ""])
    groups = deformations(rows)
    md = head + ["The paper's voxel model detecting only (force 0) under %d deformations (results/region.csv, "
                 "tables/region.md). A region detects everything when no truly penetrating guest node lies outside "
                 "it at any measured step (outside peak 0), its recall over the run is at least %g, and its precision "
                 "is above %sthat of the cheapest broad phase, flagging every guest node inside the overlap of the two "
                 "bodies' boxes (flag-overlap, the overlap region with no margin's flag-region: it does not flag "
                 "everything; flag-region: every guest node in the region's own box; flag-all: every guest node). The "
                 "large regions: the grid over the host's whole box (full) at every margin. A truly penetrating guest "
                 "node lies inside the host's box, so nothing lies outside the full region by construction: for it the "
                 "test is recall and precision. One comparison per deformation: for when every large region detects "
                 "everything; a deformation in which no penetrating node leaves the half region does not test the "
                 "claim." % (len(groups), RECALL_ALL, "" if PRECISION_GAIN == 1 else "%g times " % PRECISION_GAIN), ""]
    outcomes, half_peaks, response = [], [], []
    for name, rs in groups:
        det = with_baseline([r for r in rs if r.get("force") == "F=0"])
        on_rows = with_baseline([r for r in rs if r.get("force") != "F=0"])  # the response on: shown, not counted
        on = large(on_rows)
        o = outcome(det)
        outcomes.append(o)
        half_peaks += [r["outside_peak"] for r in det if r["region"] == "half" and not math.isnan(r["outside_peak"])]
        md += ["### %s (`%s`)" % (name, rs[0]["scene"]), "",
               "| force | region | margin | stability | outside peak | outside share | recall | precision | flag-all | "
               "flag-region | flag-overlap | region (voxels) | large | detects all |",
               "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|"]
        big = {id(r) for r in large(det) + on}
        for r in det + on_rows:
            md.append("| %s | %s | %d | %s | %.3g | %.3g | %.4g | %.3g | %.3g | %.3g | %.3g | %.4g | %s | %s |" % (
                r["force"], r["region"], r["margin"], r["stability"], r["outside_peak"], r["outside_share"],
                r["recall"], r["precision"], r["precision_flag_all"], r["precision_flag_region"], r["flag"],
                r["region_voxels_mean"], "yes" if id(r) in big else "no", "yes" if detects_all(r) else "no"))
        stable = [r for r in on if rules.counts_stable(r["stability"])]
        response.append((name, len(stable), len(on), sum(detects_all(r) for r in stable)))
        md += ["", "Outcome: %s. With the response on: %d of %d large-region runs stable (an unstable run tests "
               "nothing), %d of them detect everything." % ({"a": "for: every large region detects everything",
                                 "b": "against: %s" % "; ".join(
                                     "%s margin %d: %s" % (r["region"], r["margin"], why_not(r)) for r in large(det)
                                     if not detects_all(r)),
                                 rules.MISSING: "not judged: no penetrating node left the half region"}[o],
                                response[-1][1], response[-1][2], response[-1][3]), ""]
    verdict = rules.claim_verdict(outcomes, "a")
    own = {}
    for v in OWN_VARIANTS:
        own.setdefault(rules.claim_verdict([outcome([r for r in rs if r.get("force") == "F=0"], *v)
                                            for _n, rs in groups], "a"), []).append(v)
    agree = len(own.get(verdict, []))
    flips = ["%s under %d: %s" % (vv, len(vs), ", ".join("(recall %g, gain %g, outside %s, large by %s, flag-%s)" % v
                                                         for v in vs[:3]) + (" ..." if len(vs) > 3 else ""))
             for vv, vs in own.items() if vv != verdict]
    own_text = ("robust over its own thresholds: %d of %d (recall 0.95, 0.99, 1; precision above 1.01, 1.05, 1.5, 2 times "
                "the baseline, flag-overlap or flag-region; outside at its peak or over the window; large: full, "
                "full and overlap, or by size)" % (
                    agree, len(OWN_VARIANTS)) if not flips else
                "fragile over its own thresholds: %d of %d agree; %s" % (agree, len(OWN_VARIANTS), "; ".join(flips)))
    half_out = max(half_peaks, default=math.nan)
    t = rules.tally(outcomes, "a")
    decisive = t["for"] + t["against"] + t["noise"]
    knife = ("" if not decisive or abs(t["for"] - (1.0 - rules.MIXED_SHARE) * decisive) > 1e-9 else
             "%d of %d for is exactly the bound between supported and mixed (a share of %g against): one comparison "
             "more against and it is mixed" % (t["for"], decisive, rules.MIXED_SHARE))
    md += [verdict_line("(e)", verdict, outcomes, rule="one comparison per deformation, its large regions"), "",
           "**The claim's own thresholds:** %s." % own_text, ""] + (["**On the edge:** %s." % knife, ""] if knife else [])
    if knife and not flips:
        flips = [knife]
        own_text += "; " + knife
    resp = "; ".join("%s %s of %d" % (n, "none" if s == 0 else "%d" % s, t) for n, s, t, _d in response)
    macros = tally_macros("ClaimE", verdict, outcomes) + [
        ("ClaimEHalfOutside", "%d" % half_out if not math.isnan(half_out) else "--"),
        ("ClaimERecallAll", "%g" % RECALL_ALL), ("ClaimEPrecisionGain", "%g" % PRECISION_GAIN),
        ("ClaimEDeformations", ", ".join(n for n, _r in groups)), ("ClaimEOwn", own_text),
        ("ClaimEResponse", resp), ("ClaimEBaseline", "flag-overlap"), ("ClaimEKnife", knife or "--")]
    return Verdict("e_region", verdict, md, macros, data=outcomes,
                   own={"ClaimE": own_text} if flips else None, rule_free=["ClaimE"])
