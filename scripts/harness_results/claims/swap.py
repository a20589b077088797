"""Which body carries the grid (left open by the paper), on results/swap.csv (scripts/study.py swap):
a finding, judged by the rule of claim (a) (a position error smaller beyond the noise between two
runs that are evidence) with one addition (rules.decide_stable_wins): where one placement's run is
evidence (stable, helps, tunnels nothing) and the other's is not (not stable, tunnels, or no better
than no force), the evidence wins. Per
setting, the grid as the scene has it against swapped.
"""

from .. import rules
from .common import Verdict, exception_record, figure, floor_mm, scene_cell, word

NUMBERS = ["pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "recall",
           "true_pen_final", "t_contact_us", "voxel_mm", "margin"]


def robustness_line(judged, rows=()):
    """The finding's counts under every variant of the rule's choices (robustness.VARIANTS): how many
    distinct counts, and the variants that move them."""
    from .. import robustness
    counts = {}
    for v in robustness.VARIANTS:
        with rules.using(v):
            t = rules.tally(judged(), "a")
        counts.setdefault((t["for"], t["against"], t["noise"], t["not judged"]), []).append(v)
    default = max(counts, key=lambda k: any(v.name() == "the rule as written" for v in counts[k]))
    moved = {k: vs for k, vs in counts.items() if k != default}
    rows = list(rows)  # swap.csv as the claim read it
    if rows and all(r.get("rho_norm") == "loading" for r in rows):
        norm = "swap.csv's runs recorded rho over the loading period already"
    else:
        norm = ("swap.csv records no run lengths, so rho over the loading period cannot be applied to it; under that "
                "normalisation a run unstable by a small margin here could read marginal")
    if not moved:
        return ("**Robustness:** the same counts under all %d variants of the rule's choices (%s)." % (
            len(robustness.VARIANTS), norm))
    return ("**Robustness:** %d different counts over the %d variants of the rule's choices: %s. %s." % (
                len(counts), len(robustness.VARIANTS), "; ".join(
                    "%d-%d-%d-%d in %d (e.g. %s)" % (k + (len(vs), vs[0].name())) for k, vs in sorted(moved.items())),
                norm))


def judge(ctx):
    sw = ctx.window_csv("swap.csv", NUMBERS)
    if not sw:
        return Verdict("swap", rules.NOT_TESTED, ["## Which body carries the grid (host and guest swapped)", "",
                                                  "Not tested: results/swap.csv is missing or predates the window "
                                                  "figures (rerun `scripts/study.py swap`).", ""])
    md = ["## Which body carries the grid (host and guest swapped)", "",
          "The paper leaves open which body carries the grid. The voxel model as the scene has it and with the roles "
          "swapped, against the reference over the final window (scripts/study.py swap, results/tables/swap.md); "
          "judged by the rule of claim (a): a position error smaller beyond the noise between two runs that are "
          "evidence (stable, helps, tunnels nothing); and where one placement's run is evidence and the other's is "
          "not (not stable, tunnels, or no better than no force), the evidence wins; pairs in which neither run is "
          "evidence are not judged.", "",
          "| scenario | elim. | force | voxel (mm) | grid as the scene (mm) | grid swapped (mm) | better |",
          "|---|---|---|---:|---:|---:|---|"]
    settings = {}
    for r in sw:
        settings.setdefault((r["scene"], r["eliminator"], r["force"], r["voxel_mm"]), {})[r["swapped"]] = r
    pairs = [(scene, elim, force, vox, pair["no"], pair["yes"]) for (scene, elim, force, vox), pair in
             sorted(settings.items()) if "no" in pair and "yes" in pair]

    floors = {}  # (scene, the rule's floor choice) -> mm: read once, not once per variant

    def floor_of(scene):
        key = (scene, rules.CURRENT.floor, rules.CURRENT.reference)
        if key not in floors:
            floors[key] = floor_mm(ctx, scene)
        return floors[key]

    def judged():
        return [rules.decide_stable_wins(a, b, floor=floor_of(scene)) for scene, _e, _f, _v, a, b in pairs]

    outcomes = judged()
    for (scene, elim, force, vox, a, b), o in zip(pairs, outcomes):
        md.append("| %s | %s | %s | %g | %s (grid on %s) | %s (grid on %s) | %s |" % (
            scene_cell(ctx, scene), elim, force, vox, figure(a), a["host"], figure(b), b["host"], word(o, "as the scene", "swapped")))
    t = rules.tally(outcomes, "a")
    md += ["", "**Finding:** the grid as the scenes place it is better in %d of %d settings, swapped in %d, within the "
           "noise in %d, not judged in %d (a run not evidence, the other not an evidence run against an unstable one)."
           % (t["for"], len(outcomes), t["against"], t["noise"], t["not judged"]), "",
           # claims.md shows the rule as written's text; under the other variants (robustness.judge_variants
           # reads their macros only) the line is not made: it loops over every variant itself
           robustness_line(judged, sw) if rules.CURRENT is rules.DEFAULT else "", ""]
    macros = [("SwapSceneWins", str(t["for"])), ("SwapSwappedWins", str(t["against"])),
              ("SwapNoise", str(t["noise"])), ("SwapNotJudged", str(t["not judged"])), ("SwapSettings", str(len(outcomes)))]
    general = [rules.decide(a, b, floor=floor_of(scene)) for scene, _e, _f, _v, a, b in pairs]
    rests = exception_record(outcomes, general, "pairs in which one placement's run is evidence and the other's is "
                             "not (the swap's own rule: the evidence wins; the general rule does not judge them)")
    if rests:
        md.insert(-1, "**The finding's own rule:** %s." % rests["text"])
        md.insert(-1, "")
    return Verdict("swap", None, md, macros, data=outcomes, rests={"Swap": rests} if rests else None)
