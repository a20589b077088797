"""Which body carries the grid (left open by the paper), on results/swap.csv (scripts/study.py swap):
a finding, not a verdict. Per setting, the grid as the scene has it against swapped: better is
stable where the other is not, else a pos_err_max smaller by over 5 %; a tie otherwise.
"""

from .common import Verdict

SWAP_TIE = 0.05  # position errors within 5 % of each other are a tie
# Numbers of swap.csv and region.csv (NaN where a file lacks the column).
NUMBERS = ["pos_err_max_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "recall", "true_pen_final",
           "t_contact_us", "voxel_mm", "margin"]


def judge(ctx):
    sw = ctx.csv("swap.csv", NUMBERS)
    if not sw:
        return Verdict("swap")
    md = ["## Which body carries the grid (host and guest swapped)", "",
          "The paper leaves open which body carries the grid. The voxel model as the scene has it and with the "
          "roles swapped, against the reference (scripts/study.py swap, results/tables/swap.md).", "",
          "| scenario | elim. | force | voxel (mm) | grid on | pos. error (mm) | gap (mm) | peak depth (mm) | "
          "recall | stable | better |", "|---|---|---|---:|---|---:|---:|---:|---:|---|---|"]
    settings = {}
    for r in sw:
        settings.setdefault((r["scene"], r["eliminator"], r["force"], r["voxel_mm"]), {})[r["swapped"]] = r
    wins = {"no": 0, "yes": 0}
    for key, pair in settings.items():
        if "no" not in pair or "yes" not in pair:
            continue
        a, b = pair["no"], pair["yes"]
        # Better: stable where the other is not; else a pos_err_max smaller by over SWAP_TIE (a tie otherwise).
        if (a["stable"] == "yes") != (b["stable"] == "yes"):
            better = "no" if a["stable"] == "yes" else "yes"
        elif a["pos_err_max_mm"] < (1 - SWAP_TIE) * b["pos_err_max_mm"]:
            better = "no"
        elif b["pos_err_max_mm"] < (1 - SWAP_TIE) * a["pos_err_max_mm"]:
            better = "yes"
        else:
            better = None
        if better:
            wins[better] += 1
        for r in (a, b):
            md.append("| %s | %s | %s | %g | %s | %.3g | %.3g | %.3g | %.3g | %s | %s |" % (
                r["scene"], r["eliminator"], r["force"], r["voxel_mm"], r["host"], r["pos_err_max_mm"],
                r["gap_max_mm"], r["max_depth_peak_mm"], r["recall"], r["stable"],
                "yes" if better == r["swapped"] else ""))
    n = len([1 for p in settings.values() if "no" in p and "yes" in p])
    md += ["", "**Finding:** the grid as the scenes place it (on the left sphere, the layer, the implant) is "
           "better (stable where the other is not, else a position error smaller by over %d %%) in %d of %d "
           "settings, swapped in %d, a tie in %d." % (100 * SWAP_TIE, wins["no"], n, wins["yes"],
                                                     n - wins["no"] - wins["yes"]), ""]
    macros = [("SwapSceneWins", str(wins["no"])), ("SwapSwappedWins", str(wins["yes"])), ("SwapSettings", str(n)),
              ("SwapTies", str(n - wins["no"] - wins["yes"]))]
    return Verdict("swap", None, md, macros, data=wins)
