"""Claim (a) without its confound, on results/orient.csv (scripts/study.py orient). The paper's line
points from the nearest host node to the guest node, its plane agrees with the host's outward
normals: comparing them mixes the rule with its orientation. Both rules run with both orientations
(`orient`: guest, outward) over the force x voxel grid on the implant. Better (rules.better_of):
stable where the other is not, else a position error against the reference smaller by over 10 %; a
tie otherwise; both unstable: not judged. Verdict: supported when the plane is better in more than
half of the judged settings with each orientation, not supported when it is better in no more
settings than the line over both, partly supported otherwise.
"""

from ..rules import better_of
from .common import Verdict

ORIENT_TIE = 0.10  # position errors within 10 % of each other are a tie


def judge(ctx):
    """claims.md section: claim (a) with line and plane oriented the same way (orient.csv)."""
    rows = ctx.csv("orient.csv", ["pos_err_max_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm",
                                  "true_pen_final", "voxel_mm", "t_contact_us"])
    if not rows:
        return Verdict("a_orient", "not tested")
    cell = {(r["force"], r["voxel_mm"], r["eliminator"], r["orient"]): r for r in rows}
    settings = sorted({(r["force"], r["voxel_mm"]) for r in rows}, key=lambda k: (k[0], k[1]))
    md = ["## (a) without its confound: line and plane oriented the same way", "",
          "The paper's line points from the nearest host node to the guest node, its plane agrees with the host's "
          "outward normals: comparing them mixes the rule with its orientation. Here both rules run with both "
          "orientations (`orient`: `guest`, `outward`) over the force x voxel grid on the implant (scripts/study.py "
          "orient, results/tables/orient.md). Better: stable where the other is not, else a position error against "
          "the reference smaller by over %d %%; a tie otherwise; both unstable: not judged. The verdict: supported when "
          "the plane is better in more than half of the judged settings with each orientation, not supported when "
          "it is better in no more settings than the line over both, partly supported otherwise." % (100 * ORIENT_TIE), "",
          "| force | voxel (mm) | line guest | plane guest | line outward | plane outward | plane vs line (guest) | "
          "plane vs line (outward) | paper's pair (line guest vs plane outward) |", "|---|---:|---:|---:|---:|---:|---|---|---|"]
    tally = {"guest": [0, 0, 0], "outward": [0, 0, 0], "paper": [0, 0, 0], "line": [0, 0, 0], "plane": [0, 0, 0]}

    def word(b, a_name, b_name, x, y):
        if b is None:
            return "both unstable" if x["stable"] != "yes" and y["stable"] != "yes" else "tie"
        return a_name if b == "a" else b_name

    def fmt(r):
        return "%.3g%s" % (r["pos_err_max_mm"], "" if r["stable"] == "yes" else " (unstable)")
    for force, vox in settings:
        try:
            lg, pg = cell[(force, vox, "line", "guest")], cell[(force, vox, "plane", "guest")]
            lo, po = cell[(force, vox, "line", "outward")], cell[(force, vox, "plane", "outward")]
        except KeyError:
            continue
        res = {}
        for name, (l, p) in {"guest": (lg, pg), "outward": (lo, po), "paper": (lg, po)}.items():
            b = better_of(p, l, tie=ORIENT_TIE)
            res[name] = b
            judged = not (l["stable"] != "yes" and p["stable"] != "yes")
            tally[name][0 if b == "a" else 1 if b == "b" else 2] += 1 if judged else 0
        for name, (g, o) in {"line": (lg, lo), "plane": (pg, po)}.items():
            b = better_of(o, g, tie=ORIENT_TIE)
            tally[name][0 if b == "a" else 1 if b == "b" else 2] += 1 if not (g["stable"] != "yes" and o["stable"] != "yes") else 0
        md.append("| %s | %g | %s | %s | %s | %s | %s | %s | %s |" % (
            force, vox, fmt(lg), fmt(pg), fmt(lo), fmt(po), word(res["guest"], "plane", "line", pg, lg),
            word(res["outward"], "plane", "line", po, lo), word(res["paper"], "plane", "line", po, lg)))
    # Supported: the plane better in more than half of the judged settings with each orientation;
    # not supported: the plane better in no more settings than the line, over both orientations.
    judged = [sum(tally[k]) for k in ("guest", "outward")]
    wins = [tally["guest"][0], tally["outward"][0]]
    losses = tally["guest"][1] + tally["outward"][1]
    if all(j > 0 and w > j / 2 for w, j in zip(wins, judged)):
        va = "supported"
    elif sum(wins) <= losses:
        va = "not supported"
    else:
        va = "partly supported"
    md += ["", "**Verdict (a) without the confound: %s** — with both oriented toward the guest node the plane is better "
           "than the line in %d of %d judged settings (the line in %d); with both oriented outward, in %d of %d (the line "
           "in %d). The paper's own pair (line toward the guest, plane outward): plane better in %d of %d, line in %d. "
           "Orientation alone: outward better than toward the guest for the line in %d of %d settings (worse in %d), for "
           "the plane in %d of %d (worse in %d)." % (
               va, tally["guest"][0], judged[0], tally["guest"][1], tally["outward"][0], judged[1], tally["outward"][1],
               tally["paper"][0], sum(tally["paper"]), tally["paper"][1], tally["line"][0], sum(tally["line"]),
               tally["line"][1], tally["plane"][0], sum(tally["plane"]), tally["plane"][1]), ""]
    macros = [("ClaimAOVerdict", va), ("ClaimAOSettings", str(len(settings))),
              ("ClaimAOGuestWins", str(tally["guest"][0])), ("ClaimAOGuestJudged", str(judged[0])),
              ("ClaimAOGuestLine", str(tally["guest"][1])), ("ClaimAOOutWins", str(tally["outward"][0])),
              ("ClaimAOOutJudged", str(judged[1])), ("ClaimAOOutLine", str(tally["outward"][1])),
              ("ClaimAOPaperWins", str(tally["paper"][0])), ("ClaimAOPaperJudged", str(sum(tally["paper"]))),
              ("ClaimAOPaperLine", str(tally["paper"][1])),
              ("ClaimAOLineOut", str(tally["line"][0])), ("ClaimAOLineJudged", str(sum(tally["line"]))),
              ("ClaimAOLineGuest", str(tally["line"][1])), ("ClaimAOPlaneOut", str(tally["plane"][0])),
              ("ClaimAOPlaneJudged", str(sum(tally["plane"]))), ("ClaimAOPlaneGuest", str(tally["plane"][1]))]
    return Verdict("a_orient", va, md, macros, data=tally)
