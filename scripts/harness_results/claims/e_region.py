"""Claim (e), section 3: "if voxels are built for large space area near penetrating bodies then
collisions are detected for any deformations", on results/region.csv (scripts/study.py region):
supported when the full region's recall is at least that of half and overlap (within 0.01) and at
least RECALL_ALL in every scene and margin; partly when it is at least theirs everywhere or reaches
RECALL_ALL somewhere; not supported otherwise.
"""

import math

from .common import Verdict
from .swap import NUMBERS

RECALL_ALL = 0.9  # "collisions are detected": at least 90 % of the penetrating guest nodes


def judge(ctx):
    rg = ctx.csv("region.csv", NUMBERS)
    if not rg:
        return Verdict("e_region", "not tested")
    md = ["## (e) A large region detects collisions under any deformation", "",
          "The voxel model's grid over half of the host's box (facing the guest), the whole box, or the boxes' "
          "overlap, with 0, 1 or 3 voxels of margin, on the two scenes whose bodies deform most "
          "(scripts/study.py region, results/tables/region.md). Collisions count as detected when at least "
          "%d %% of the truly penetrating guest nodes are reported (recall, CGAL every 10 steps)." % (100 * RECALL_ALL),
          "", "| scenario | margin | recall half | recall full | recall overlap | pos. error half (mm) | "
          "full | overlap | time half (µs) | full | overlap |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    cells = {}
    for r in rg:
        cells.setdefault((r["scene"], int(r["margin"])), {})[r["region"]] = r
    full_best, full_all, total, region_matters = 0, 0, 0, 0
    recalls = []
    for (scene, m), g in sorted(cells.items()):
        if not all(k in g for k in ("half", "full", "overlap")):
            continue
        total += 1
        rf = g["full"]["recall"]
        recalls.append(rf)
        if rf >= max(g["half"]["recall"], g["overlap"]["recall"]) - 0.01:
            full_best += 1
        if rf >= RECALL_ALL:
            full_all += 1
        rs = [g[k]["recall"] for k in ("half", "full", "overlap")]
        if max(rs) - min(rs) > 0.01:
            region_matters += 1
        md.append("| %s | %d | %.3f | %.3f | %.3f | %.3g | %.3g | %.3g | %.0f | %.0f | %.0f |" % (
            scene, m, g["half"]["recall"], rf, g["overlap"]["recall"], g["half"]["pos_err_max_mm"],
            g["full"]["pos_err_max_mm"], g["overlap"]["pos_err_max_mm"], g["half"]["t_contact_us"],
            g["full"]["t_contact_us"], g["overlap"]["t_contact_us"]))
    if total and full_all == total and full_best == total:
        verdict = "supported"
    elif total and (full_best == total or full_all > 0):
        verdict = "partly supported"
    else:
        verdict = "not supported"
    md += ["", "**Verdict (e): %s** — the full region detects at least as many of the penetrating nodes as half "
           "and overlap in %d of %d scene-margin settings, and at least %d %% of them in %d (its recall %.2f to "
           "%.2f)." % (verdict, full_best, total, 100 * RECALL_ALL, full_all, min(recalls) if recalls else math.nan,
                       max(recalls) if recalls else math.nan), ""]
    md += ["The region changes the recall by more than 0.01 in %d of %d settings." % (region_matters, total), ""]
    macros = [("ClaimERegionMatters", str(region_matters)),
              ("ClaimEVerdict", verdict), ("ClaimEFullBest", str(full_best)), ("ClaimEAll", str(full_all)),
              ("ClaimESettings", str(total)),
              ("ClaimERecallMin", "%.2f" % (min(recalls) if recalls else math.nan)),
              ("ClaimERecallMax", "%.2f" % (max(recalls) if recalls else math.nan))]
    return Verdict("e_region", verdict, md, macros)
