"""Claim (e), section 3: "if voxels are built for large space area near penetrating bodies then
collisions are detected for any deformations". Judged on results/region.csv (scripts/study.py
region: experiments/scenes/claims/region_wrap.json, a skin pulled around a limb below the limb's
centre), with detection alone (force 0: the same deformation for every region): a region detects
"for any deformation" when no truly penetrating guest node lies outside it (outside share 0 over
the final window) and it detects at least RECALL_ALL of the penetrating guest nodes over the run.
The claim predicts that the large regions (full, overlap; with any margin) do; the comparison is
against it when one of them does not. The half region is shown beside it: the scene exercises the
claim only if guest nodes do leave the half region (its outside share above zero); if none does,
the claim is not tested.
"""

import math

from .. import rules
from .common import Verdict, tally_macros, verdict_line

RECALL_ALL = 0.99
NUMBERS = ["outside_share", "outside_mean", "outside_peak", "pen_guest_mean", "recall", "depth_max_mm",
           "max_depth_peak_mm", "t_contact_us", "margin"]


def detects_all(r):
    return (not math.isnan(r["outside_share"]) and r["outside_share"] == 0.0 and not math.isnan(r["recall"])
            and r["recall"] >= RECALL_ALL)


def judge(ctx):
    rows = ctx.csv("region.csv", NUMBERS)
    head = ["## (e) A large region detects collisions under any deformation", ""]
    if not rows:
        return Verdict("e_region", rules.NOT_TESTED, head + ["Not tested: results/region.csv is missing.", ""])
    det = [r for r in rows if r.get("force") == "F=0"]
    md = head + ["`%s`, the paper's voxel model detecting only (force 0). Outside share: truly penetrating skin "
                 "nodes outside the grid's region over all truly penetrating skin nodes (window mean); recall over "
                 "the run. A region detects everything when its outside share is 0 and its recall at least %g." % (
                     rows[0]["scene"], RECALL_ALL), "",
                 "| region | margin (voxels) | stability | outside share | penetrating (nodes) | recall | detects all |",
                 "|---|---:|---|---:|---:|---:|---|"]
    for r in det:
        md.append("| %s | %d | %s | %.3g | %.3g | %.3g | %s |" % (
            r["region"], r["margin"], r["stability"], r["outside_share"], r["pen_guest_mean"], r["recall"],
            "yes" if detects_all(r) else "no"))
    half_out = max((r["outside_share"] for r in det if r["region"] == "half" and not math.isnan(r["outside_share"])),
                   default=math.nan)
    if not (half_out > 0):
        verdict, outcomes = rules.NOT_TESTED, []
        md += ["", "**Verdict (e): not tested**: no penetrating guest node left the half region (largest outside "
               "share %.3g): the scene does not exercise the claim." % half_out, ""]
    else:
        # Detection alone has no contact force: stability is not what decides here (nothing pushes).
        outcomes = ["a" if detects_all(r) else "b" for r in det if r["region"] in ("full", "overlap")]
        verdict = rules.claim_verdict(outcomes, "a")
        md += ["", verdict_line("(e)", verdict, outcomes, rule="the large regions (full, overlap) at every margin; "
                                "the half region leaves up to %.3g of the penetrating guest nodes outside it" % half_out), ""]
    pen = [r for r in rows if r.get("force") not in (None, "F=0")]
    if pen:
        md += ["With the penalty force the same regions give (depth: deepest node, window maximum):", "",
               "| region | margin | stability | outside share | recall | depth (mm) | peak depth (mm) |",
               "|---|---:|---|---:|---:|---:|---:|"]
        for r in pen:
            md.append("| %s | %d | %s | %.3g | %.3g | %.3g | %.3g |" % (
                r["region"], r["margin"], r["stability"], r["outside_share"], r["recall"], r["depth_max_mm"],
                r["max_depth_peak_mm"]))
        md.append("")
    macros = tally_macros("ClaimE", verdict, outcomes) + [("ClaimEHalfOutside", "%.2g" % half_out),
                                                          ("ClaimERecallAll", "%g" % RECALL_ALL)]
    return Verdict("e_region", verdict, md, macros, data=outcomes)
