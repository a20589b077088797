"""Claims (a), (b) and the host/guest swap judged again where the paper's model is at its best, on
results/regime.csv (scripts/study.py regime: the paper's voxel model over forces, voxels and regimes:
the scene as written, dt / 8, the grid over the host's full box, and a damping term on the contact
force, named as a variant and not the paper's method). Each verdict lists the regimes its decisive
comparisons come from.

  (a) in the regimes   per (regime, voxel, force): the plane against the line by claim (a)'s rule
                       (rules.decide: both evidence, error smaller beyond the noise);
  (b) in the regimes   per run that is evidence (stable, helps, tunnels nothing: "there", where the
                       model helps): its guest's episodes against (b)'s three criteria (b_episodes);
                       a run that is not evidence is not judged, with why;
  swap in the regimes  per setting whose scene placement is evidence: as the scene has it against
                       swapped, by the swap's rule (rules.decide_stable_wins: the unstable side loses).

The scene's placement is measured against the reference of the model's kind (one-sided where the
scene has one) with the two-sided error beside it; (a) and (b) judge it on its kind. The swap judges
both placements on their two-sided errors (the one-sided reference is the limit of the scene's
placement only; the swapped runs are measured against the two-sided one).
"""

from .. import reader, rules
from . import b_episodes
from ..studies import regime as study
from .common import Verdict, figure, floor_mm, scene_cell, tally_macros, verdict_line

NUMBERS = ["pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm", "tunnelled", "voxel_mm",
           "contact_power_ratio", "ep_episodes", "ep_p90", "ep_failed_frac", "ep_peak_frac"]
NO_FORCE = rules.NO_FORCE


def regimes_text(items):
    """"as written+dt/8 (3), damping 0.1 (2)": the regimes of the decisive comparisons, by count; "none"."""
    counts = {}
    for r in items:
        if r is None:
            continue
        counts[r] = counts.get(r, 0) + 1
    return ", ".join("%s (%d)" % kv for kv in sorted(counts.items(), key=lambda kv: -kv[1])) or "none"


# (b)'s own thresholds, varied in the regimes: (p90 in the scene's steps, failed share, peak share);
# the first is the claim's as written (b_episodes).
B_OWN = [(p, f, k) for p in (100, 200, 400) for f in (0.05, 0.10) for k in (0.05, 0.10)]


def b_outcome(r, p90_max=100, failed_max=0.05, peak_max=0.05):
    """(b) on one run of the regime study: why not judged (not evidence, no episodes), "a" when its
    guest's episodes meet the three criteria, "b" when not."""
    gap = rules.evidence_gap(r)
    if gap is not None:
        return gap
    if not reader.present(r.get("ep_episodes")):
        return rules.MISSING
    fails = b_episodes.failing_criteria(reader.num(r.get("ep_peak_frac"), 0.0), reader.num(r.get("ep_p90")),
                                        reader.num(r.get("ep_failed_frac"), 0.0), p90_max, failed_max, peak_max)
    return "b" if fails else "a"


FAMILIES = ["paper", "damped"]
FAMILY_NAME = {"paper": "the paper's method (as written, dt / 8, full region)",
               "damped": "with the damping variant (not the paper's method)"}


def family(regime):
    """"paper" for the regimes that change only the numerics; "damped" for the damping variant."""
    return "damped" if regime.startswith("damping") else "paper"


def configurations(by, fam):
    """{configuration key: [(regime, outcome)]} of family `fam` in `by` ({(fam, scene, ...): [(regime,
    outcome)]}): the paper's regimes of one setting together; a damping strength a configuration of
    its own (its regime in the key)."""
    groups = {}
    for key, items in by.items():
        if key[0] != fam:
            continue
        if fam == "damped":
            for reg, o in items:
                groups.setdefault(key + (reg,), []).append((reg, o))
        else:
            groups.setdefault(key, []).extend(items)
    return groups


def combined(by, fam):
    """[(outcome, regimes)] per configuration of family `fam` in `by` (configurations()): one outcome
    per configuration: its regimes' decisive outcome where they agree, within the noise where they
    disagree, else the first regime's reason it is not judged."""
    groups = configurations(by, fam)
    out = []
    for key in sorted(groups, key=str):
        items = groups[key]
        dec = [(reg, o) for reg, o in items if decisive(o)]
        if not dec:
            out.append((items[0][1], None))
        elif len({o for _r, o in dec}) == 1:
            out.append((dec[0][1], "+".join(reg for reg, _o in dec)))
        else:
            out.append((rules.WITHIN_NOISE, "+".join(reg for reg, _o in dec)))
    return out


def two_sided(ctx, r):
    """The scene placement's row `r` on its two-sided error (rules.as_two_sided), its helps judged
    again on it against the scene's run without contact force: what the swap compares with the
    swapped run (measured against the two-sided reference). `r` itself where it is two-sided already."""
    return rules.two_sided_row(r, ctx.no_force(r["scene"]))


def evidence_by_scene(own):
    """"N of M on implant_expansion, ...": the scene placement's runs that are evidence, per scene."""
    return ", ".join("%d of %d on \\code{%s}" % (sum(1 for r in own if r["scene"] == sc and rules.evidence_gap(r) is None),
                                                 sum(1 for r in own if r["scene"] == sc), sc.replace("_", "\\_"))
                     for sc in sorted({r["scene"] for r in own}))


def line_evidence(own):
    """"N of its M": the line's runs with the paper's method (not the damping variant) that are evidence."""
    line = [r for r in own if r["eliminator"] == "line" and family(r["regime"]) == "paper"]
    return "%d of its %d" % (sum(1 for r in line if rules.evidence_gap(r) is None), len(line))


def dt_class_changes(own):
    """"N of M": the settings (scene, eliminator, voxel, force) whose stability class at dt / 8 differs
    from the class as written."""
    by = {}
    for r in own:
        if r["regime"] in ("as written", "dt/8"):
            by.setdefault((r["scene"], r["eliminator"], r["voxel_mm"], r["force"]), {})[r["regime"]] = r.get("stability")
    pairs = [v for v in by.values() if len(v) == 2]
    return "%d of %d" % (sum(1 for v in pairs if v["as written"] != v["dt/8"]), len(pairs))


def decisive_scenes(by, fam, tex=False):
    """"sphere_collision (3)": the scenes of family `fam`'s configurations in `by` that have a decisive
    outcome (counted as combined() counts them), "none"."""
    counts = {}
    for key, items in configurations(by, fam).items():
        if any(decisive(o) for _r, o in items):
            counts[key[1]] = counts.get(key[1], 0) + 1
    name = (lambda sc: "\\code{%s}" % sc.replace("_", "\\_")) if tex else (lambda sc: sc)
    return ", ".join("%s (%d)" % (name(sc), n) for sc, n in sorted(counts.items())) or "none"


def holds_not_evidence(own, fam=None):
    """"N (marginal M, ...); K more with no episode": the scene placement's runs (of family `fam`, or
    all) that are not evidence but whose episodes, where they have some, meet (b)'s three criteria, by
    why they are not evidence; runs with no episode at all (nothing to judge: the force held the
    bodies apart, or nothing touched) counted apart; "none"."""
    why, empty = {}, 0
    for r in own:
        if fam is not None and family(r["regime"]) != fam:
            continue
        gap = rules.evidence_gap(r)
        if gap is None or not reader.present(r.get("ep_episodes")):
            continue
        if reader.num(r.get("ep_episodes"), 0.0) == 0:
            empty += 1
        elif b_outcome(dict(r, stable="yes", stability="stable", helps="yes", useless="", tunnelled=0.0)) == "a":
            label = r.get("stability") if r.get("stability") in ("marginal", "unstable") else gap
            why[label] = why.get(label, 0) + 1
    n = sum(why.values())
    text = "%d (%s)" % (n, ", ".join("%s %d" % kv for kv in sorted(why.items()))) if n else "none"
    return text + ("; %d more with no episode to judge" % empty if empty else "")


def decisive(o):
    return o in ("a", "b", rules.WITHIN_NOISE)


def judge(ctx):
    rows = ctx.window_csv("regime.csv", NUMBERS)
    title = "## The paper's model at its best: (a), (b) and the swap in the regime search"
    if not rows:
        md = [title, "", "Not tested: results/regime.csv is missing (`scripts/study.py regime`).", ""]
        return Verdict("regime", rules.NOT_TESTED, md, tally_macros("ClaimARegime", rules.NOT_TESTED, []) +
                       tally_macros("ClaimBRegime", rules.NOT_TESTED, []))
    md = [title, "",
          "results/regime.csv (`scripts/study.py regime`, tables/regime.md): the paper's voxel model with the line and "
          "the plane, forces %s, the footing voxels, in each regime: as written, dt / 8, the "
          "grid over the host's full box, and a damping term on the contact force (a variant, not the paper's "
          "method). The paper says its force \"was defined experimentally for every task\"; this is that search. "
          "Each verdict lists the regimes its decisive comparisons come from. The scene's placement is measured against "
          "the reference of the model's kind (%s), (a) and (b) judge it there; the swap judges both placements on their "
          "two-sided errors." % (study.forces_text(sorted({r["scene"] for r in rows})), ", ".join(sorted({r.get("reference") or "both ways" for r in rows
                                                  if r.get("swapped") != "yes" and r["regime"] != NO_FORCE}))), "",
          "The references: %s." % "; ".join(scene_cell(ctx, sc, of_kind=True) for sc in
                                             sorted({r["scene"] for r in rows})), ""]
    own = [r for r in rows if r["regime"] != NO_FORCE and r.get("swapped") != "yes"]
    scenes = sorted({r["scene"] for r in own})
    md += ["A configuration is counted once: the regimes that change only the numerics (as written, dt / 8, the "
           "grid over the full box: the paper's method) make one comparison per configuration, their outcomes "
           "combined (the same outcome, or within the noise where they disagree); each damping strength (the "
           "variant) makes its own. The paper's method and the variant are judged apart. Not searched: regimes "
           "combined (dt / 8 with damping), the region \"overlap\", margins, forces between those listed, damping "
           "above 0.1 N s/m, voxels other than the pair's and twice it (on the sphere 16 mm, the ablation's one stable line run that helps), dt "
           "between the scene's and dt / 8; a verdict without enough decisive comparisons is inconclusive for the search's coverage "
           "(the rule's variant that counts marginal runs stable shows what a run just outside it would add).", ""]
    # (a): the plane against the line per setting.
    md += ["### (a) The plane works better than the line, in the regimes", "",
           "| scene | regime | voxel (mm) | force | line (mm) | plane (mm) | better |", "|---|---|---:|---|---:|---:|---|"]
    a_by, a_sw = {}, {}
    for scene in scenes:
        floor = floor_mm(ctx, scene, of_kind=True)  # each row against the reference it names
        sets = {}
        for r in own:
            if r["scene"] == scene:
                sets.setdefault((r["regime"], r["voxel_mm"], r["force"]), {})[r["eliminator"]] = r
        for (reg, vox, force), pair in sets.items():
            if "line" not in pair or "plane" not in pair:
                continue
            o = rules.decide(pair["plane"], pair["line"], floor=floor)
            key = (family(reg), scene, vox, force)
            a_by.setdefault(key, []).append((reg, o))
            a_sw.setdefault(key, []).append((reg, rules.decide_stable_wins(pair["plane"], pair["line"], floor=floor)))
            md.append("| %s | %s | %g | %s | %s | %s | %s |" % (
                scene, reg, vox, force, figure(pair["line"]), figure(pair["plane"]),
                {"a": "plane", "b": "line", rules.WITHIN_NOISE: "within the noise"}.get(o, "not judged (%s)" % o)))
    a_res = {fam: combined(a_by, fam) for fam in FAMILIES}
    sw_rule = {fam: rules.tally([o for o, _r in combined(a_sw, fam)], "a") for fam in FAMILIES}
    md.append("")
    for fam in FAMILIES:
        outs = [o for o, _r in a_res[fam]]
        ta = sw_rule[fam]
        md += [verdict_line("(a) in the regimes, %s" % FAMILY_NAME[fam], rules.claim_verdict(outs, "a"), outs), "",
               "Its decisive comparisons come from: %s; on: %s. By the swap's rule instead (where one eliminator's run is "
               "evidence and the other's is not, the evidence wins: a finding, not the claim's rule, which compares "
               "errors): the plane in %d, the line in %d, within the noise %d, neither evidence %d." % (
                   regimes_text([r for o, r in a_res[fam] if decisive(o)]), decisive_scenes(a_by, fam), ta["for"],
                   ta["against"], ta["noise"],
                   ta["not judged"]), ""]
    # (b): the episodes of the runs that are evidence.
    md += ["### (b) Penetrating points are few and eliminated within several iterations, in the regimes", "",
           "Lengths in the scene's steps: at dt / 8 a run's steps / 8, measured every 80 of its steps (10 of the "
           "scene's), the same physical time as (b)'s 100 steps at the scene's dt. An episode still open when the run "
           "ends is cut there: its length is the time from its start to the run's end (a lower bound, set by how long "
           "the run settles), and it counts as failed; a p90 near the run's length says most episodes never closed "
           "(nodes held inside the host at equilibrium), not that they were measured to last that long.", "",
           "Runs whose episodes meet the three criteria but that are not evidence (not judged): with the paper's "
           "method %s; with the damping variant %s." % (holds_not_evidence(own, "paper"), holds_not_evidence(own, "damped")), "",
           "| scene | regime | elim. | voxel (mm) | force | run | episodes | p90 (scene steps) | failed (%) | peak (% of nodes) "
           "| outcome |", "|---|---|---|---:|---|---|---:|---:|---:|---:|---|"]

    def b_grouped(v=(100, 0.05, 0.05)):
        by = {}
        for r in own:
            by.setdefault((family(r["regime"]), r["scene"], r["eliminator"], r["voxel_mm"], r["force"]), []).append(
                (r["regime"], b_outcome(r, *v)))
        return by

    def b_outcomes(v=(100, 0.05, 0.05)):
        by = b_grouped(v)
        return {fam: combined(by, fam) for fam in FAMILIES}
    b_by = b_grouped()
    # every run, the decisive ones first, each with why it is or is not decisive
    for r in sorted(own, key=lambda r: not decisive(b_outcome(r))):
        o = b_outcome(r)
        if decisive(o):
            said = "decisive: holds" if o == "a" else "decisive: fails: %s" % r.get("ep_why", "")
        else:
            said = "not judged: %s" % (r.get("stability") if o == rules.NOT_STABLE and r.get("stability") else o)
            if o != rules.MISSING and reader.present(r.get("ep_episodes")) and int(r["ep_episodes"]) > 0:
                fails = b_episodes.failing_criteria(reader.num(r.get("ep_peak_frac"), 0.0), reader.num(r.get("ep_p90")),
                                                    reader.num(r.get("ep_failed_frac"), 0.0))
                said += " (its episodes %s)" % ("fail" if fails else "meet the criteria")
        md.append("| %s | %s | %s | %g | %s | %s | %s | %s | %s | %s | %s |" % (
            r["scene"], r["regime"], r["eliminator"], r["voxel_mm"], r["force"], figure(r),
            "%d" % int(r["ep_episodes"]) if reader.present(r.get("ep_episodes")) else "-",
            "%g" % r["ep_p90"] if reader.present(r.get("ep_p90")) else "-",
            "%.1f" % (100 * reader.num(r.get("ep_failed_frac"), 0.0)) if reader.present(r.get("ep_episodes")) else "-",
            "%.2f" % (100 * reader.num(r.get("ep_peak_frac"), 0.0)) if reader.present(r.get("ep_episodes")) else "-",
            said))
    b_res = b_outcomes()
    b_own_text, b_flipped = {}, {}
    md.append("")
    for fam in FAMILIES:
        outs = [o for o, _r in b_res[fam]]
        verdict = rules.claim_verdict(outs, "a")
        var = {}
        for v in B_OWN:
            var.setdefault(rules.claim_verdict([o for o, _r in b_outcomes(v)[fam]], "a"), []).append(v)
        flips = ["%s under %d: %s" % (vv, len(vs), ", ".join("(p90 %d, failed %g %%, peak %g %%)" % (
            p, 100 * f, 100 * k) for p, f, k in vs[:4]) + (" ..." if len(vs) > 4 else "")) for vv, vs in var.items()
            if vv != verdict]
        b_own_text[fam] = ("robust over its own thresholds: %d of %d (p90 100, 200, 400 scene steps; failed 5 or 10 %%; "
                           "peak 5 or 10 %%)" % (len(var.get(verdict, [])), len(B_OWN)) if not flips else
                           "fragile over its own thresholds: %d of %d agree; %s" % (
                               len(var.get(verdict, [])), len(B_OWN), "; ".join(flips)))
        b_flipped[fam] = bool(flips)
        md += [verdict_line("(b) in the regimes, %s" % FAMILY_NAME[fam], verdict, outs), "",
               "Its decisive comparisons come from: %s; on: %s. **The claim's own thresholds:** %s." % (
                   regimes_text([r for o, r in b_res[fam] if decisive(o)]), decisive_scenes(b_by, fam), b_own_text[fam]), ""]
    # The swap: the scene's placement against swapped where the scene's is evidence.
    md += ["### Which body carries the grid, in the regimes", "",
           "Swapped only where the scene's placement is evidence against either reference (a biased sample by construction: the swapped "
           "placement had no force search of its own).", "",
           "| scene | regime | elim. | voxel (mm) | force | as the scene (mm) | swapped (mm) | better |",
           "|---|---|---|---:|---|---:|---:|---|"]
    s_by = {}
    for sw in (r for r in rows if r.get("swapped") == "yes"):
        mine = next((r for r in own if (r["scene"], r["regime"], r["eliminator"], r["voxel_mm"], r["force"]) ==
                     (sw["scene"], sw["regime"], sw["eliminator"], sw["voxel_mm"], sw["force"])), None)
        if mine is None:
            continue
        mine = two_sided(ctx, mine)
        o = rules.decide_stable_wins(mine, sw, floor=floor_mm(ctx, sw["scene"]))
        s_by.setdefault((family(sw["regime"]), sw["scene"], sw["eliminator"], sw["voxel_mm"], sw["force"]),
                        []).append((sw["regime"], o))
        md.append("| %s | %s | %s | %g | %s | %s | %s | %s |" % (
            sw["scene"], sw["regime"], sw["eliminator"], sw["voxel_mm"], sw["force"], figure(mine), figure(sw),
            {"a": "as the scene", "b": "swapped", rules.WITHIN_NOISE: "within the noise"}.get(o, "not judged (%s)" % o)))
    s_res = {fam: combined(s_by, fam) for fam in FAMILIES}
    st = {fam: rules.tally([o for o, _r in s_res[fam]], "a") for fam in FAMILIES}
    md.append("")
    for fam in FAMILIES:
        t = st[fam]
        md += ["Swap in the regimes, %s (a finding, per configuration): the scene's placement better in %d, swapped in "
               "%d, within the noise in %d, not judged %d; from: %s." % (
                   FAMILY_NAME[fam], t["for"], t["against"], t["noise"], t["not judged"],
                   regimes_text([r for o, r in s_res[fam] if decisive(o)])), ""]
    a_out, b_out = [o for o, _r in a_res["paper"]], [o for o, _r in b_res["paper"]]
    a_outd, b_outd = [o for o, _r in a_res["damped"]], [o for o, _r in b_res["damped"]]
    a_verdict, b_verdict = rules.claim_verdict(a_out, "a"), rules.claim_verdict(b_out, "a")
    macros = (tally_macros("ClaimARegime", a_verdict, a_out) + tally_macros("ClaimBRegime", b_verdict, b_out) +
              tally_macros("ClaimARegimeDamped", rules.claim_verdict(a_outd, "a"), a_outd) +
              tally_macros("ClaimBRegimeDamped", rules.claim_verdict(b_outd, "a"), b_outd))
    for fam, pre in (("paper", "ClaimARegime"), ("damped", "ClaimARegimeDamped")):
        macros.append((pre + "From", regimes_text([r for o, r in a_res[fam] if decisive(o)])))
        ta = sw_rule[fam]
        macros.append((pre + "SwapRule", "%d-%d-%d-%d" % (ta["for"], ta["against"], ta["noise"], ta["not judged"])))
    for fam, pre in (("paper", "ClaimBRegime"), ("damped", "ClaimBRegimeDamped")):
        macros += [(pre + "From", regimes_text([r for o, r in b_res[fam] if decisive(o)])), (pre + "Own", b_own_text[fam])]
    for fam, pre in (("paper", "SwapRegime"), ("damped", "SwapRegimeDamped")):
        t = st[fam]
        macros += [(pre + "SceneWins", str(t["for"])), (pre + "SwappedWins", str(t["against"])),
                   (pre + "Noise", str(t["noise"])), (pre + "NotJudged", str(t["not judged"])),
                   (pre + "From", regimes_text([r for o, r in s_res[fam] if decisive(o)]))]
    macros += [("RegimeForces", study.forces_text(scenes, tex=True)),
               ("RegimeDampings", " and ".join(x.split()[1] for x, _s in study.REGIMES if x.startswith("damping")) + "~N\\,s/m")]
    macros.append(("RegimeEvidence", "%d of %d" % (sum(1 for r in own if rules.evidence_gap(r) is None), len(own))))
    macros += [("ClaimARegimeOn", decisive_scenes(a_by, "paper", tex=True)),
               ("ClaimARegimeDampedOn", decisive_scenes(a_by, "damped", tex=True)),
               ("ClaimBRegimeOn", decisive_scenes(b_by, "paper", tex=True)),
               ("ClaimBRegimeDampedOn", decisive_scenes(b_by, "damped", tex=True)),
               ("RegimeBHoldsNotEvidence", holds_not_evidence(own, "paper")),
               ("RegimeEvidenceByScene", evidence_by_scene(own)), ("RegimeLineEvidence", line_evidence(own)),
               ("RegimeDtClassChanges", dt_class_changes(own))]
    own_map = {pre: b_own_text[fam] for fam, pre in (("paper", "ClaimBRegime"), ("damped", "ClaimBRegimeDamped"))
               if b_flipped[fam]}
    return Verdict("regime", a_verdict, md, macros, data=a_out + b_out + a_outd + b_outd, own=own_map or None)
