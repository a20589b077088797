"""State what the judge found: results/SUMMARY.md (the answer first), results/claims.md (the detail),
results/specifications.csv (each claim under every distinct specification of the remaining
choices), and for the report tables/claims_verdicts.tex and tables/claims_macros.tex."""

import csv
import itertools
import json
import math
import os

from .. import reader, runs, writers
from . import choices
from .claims import AGAINST, FOR, NOT_SUPPORTED, ORDER, SCENES, SUPPORTED, Data, g
from .measure import UNSTABLE, is_constant, measure

MADE_BY = "scripts/claims.py"
# The choices each claim's comparisons can depend on (judge/measure.py and the claim's own).
MEASURE = ["chatter_length", "contact_input_share", "floor", "tunnel_limit", "unstable_fails"]
REACHES = {
    "a": MEASURE + ["auto_force"],
    "b": ["chatter_length", "contact_input_share", "tunnel_limit", "unstable_fails", "auto_force", "b_reading", "p90_steps", "peak_share",
          "open_share"],
    "c": ["chatter_length", "contact_input_share", "tunnel_limit", "unstable_fails", "restriction_bound",
          "c_failures", "much"],
    "d": ["exact_set"],
    "e": ["e_reading", "e_miss"],
    "rt": MEASURE + ["auto_force", "rt_statistic", "rt_setting"],
    "sim": ["tunnel_limit"],
    "completed": MEASURE,
}
LETTER = {"a": "A", "b": "B", "c": "C", "d": "D", "e": "E", "rt": "RT", "sim": "Sim", "completed": "VE"}


def rounded(v):
    return None if v is None or v != v else round(v, 4)


def signature(res):
    """What a specification gives a claim: its verdict and every effect with its interval."""
    return (res.verdict,) + tuple((e.where, e.outcome, rounded(e.value), rounded(e.lo), rounded(e.hi))
                                  for e in res.effects)


def specifications(data, claim):
    """(judged, [(spec, Result)]): how many specifications of the choices that reach `claim` were
    judged, and those that give distinct results (signature), the one as written first."""
    key = claim(data, choices.DEFAULT).key
    names = REACHES[key]
    combos = itertools.product(*(choices.BY_NAME[n].values() for n in names))
    specs = sorted((choices.Spec(**dict(zip(names, c))) for c in combos), key=lambda s: len(s.changed()))
    seen, out = set(), []
    for spec in specs:
        res = claim(data, spec)
        sig = signature(res)
        if sig not in seen:
            seen.add(sig)
            out.append((spec, res))
    return len(specs), out


def reversals(specs):
    """[(spec, what)] of the distinct specifications that reverse the claim: its verdict between
    supported and not supported, or an effect's outcome between for and against at the same place."""
    base = specs[0][1]
    outcome = {e.where: e.outcome for e in base.effects}
    out = []
    for spec, res in specs[1:]:
        if {base.verdict, res.verdict} == {SUPPORTED, NOT_SUPPORTED}:
            out.append((spec, "the verdict (%s)" % res.verdict))
            continue
        flips = [e.where for e in res.effects if {outcome.get(e.where), e.outcome} == {FOR, AGAINST}]
        if flips:
            out.append((spec, ", ".join(flips)))
    return out


def stated(res, revs):
    if revs and res.verdict in (SUPPORTED, NOT_SUPPORTED):
        return "%s (fragile)" % res.verdict
    return res.verdict


def effect_cell(res):
    """The claim's effect in a few words: one effect's interval, or over several places the range of
    the effects and of their intervals' ends."""
    es = [e for e in res.effects if e.value == e.value]
    if not es:
        return "; ".join(e.note for e in res.effects)[:120] or "-"
    if len(es) == 1:
        return es[0].interval()
    lo = min(e.lo for e in es)
    hi = max(e.hi for e in es)
    rng = "%s to %s" % (g(min(e.value for e in es)), g(max(e.value for e in es)))
    if lo == min(e.value for e in es) and hi == max(e.value for e in es):
        return "%s (%d places)" % (rng, len(es))
    return "%s (%d places; interval ends %s to %s)" % (rng, len(es), g(lo), g(hi))


def places(effects, most=3):
    """The places of `effects` in words (their count past `most`)."""
    if len(effects) > most:
        return "%d places (%s, ...)" % (len(effects), effects[0].where)
    return ", ".join(e.where for e in effects) or "nowhere"


# ----------------------------------------------------------------------------------------------
# What accuracy costs: per scene, each method's best, on equal footing

def fastest_within(runs):
    """Among the runs that do not fail, the fastest whose error interval overlaps the most accurate
    one's (a tie by the intervals goes to time); None when all fail."""
    ok = [r for r in runs if not r.failed and r.err == r.err]
    if not ok:
        return None
    top = min(ok, key=lambda r: r.err)
    tied = [r for r in ok if r.err_lo <= top.err_hi and top.err_lo <= r.err_hi and r.t == r.t]
    return min(tied, key=lambda r: r.t) if tied else top


COST_GROUPS = [
    ("paper's model", lambda r: r.get("detector") == "voxel" and r.get("eliminator") in ("line", "plane")
     and is_constant(r.get("force"))),
    ("grid, auto", lambda r: r.get("detector") == "voxel" and r.get("force") == "auto"),
    ("grid, penalty", lambda r: r.get("detector") == "voxel" and r.get("force") == "k=500"),
    ("voxel_exact", lambda r: r.get("detector") == "voxel_exact"),
    ("hashing", lambda r: r.get("detector") == "hash"),
    ("CGAL", lambda r: r.get("detector") == "cgal"),
    ("FCL", lambda r: r.get("detector") == "fcl"),
]


def cost_lines(data, spec):
    """Per scene: (scene, [(label, best Run or None, runs, failing)], no-force error, constant-force
    figures). One-sided rows only (the paper's model's kind; every method against the one-sided
    reference), so that every method is on the same footing."""
    rows = data.csv("accuracy_time.csv")
    out = []
    for scene in SCENES:
        one = [r for r in rows if r.get("scene") == scene and r.get("reference") == "one-sided"]
        items = []
        for label, pred in COST_GROUPS:
            rs = [measure(r, spec, data.scenes, label=label) for r in one if pred(r)]
            items.append((label, fastest_within(rs), len(rs), sum(1 for r in rs if r.failed)))
        base = next((r for r in one if r.get("config") == "no contact force"), None)
        b0 = reader.num(base.get("pos_err_max_mm")) if base else math.nan
        const = [measure(r, spec, data.scenes) for r in one if COST_GROUPS[0][1](r)]
        const_fig = (len(const), sum(1 for r in const if "through" in r.failed),
                     sum(1 for r in const if r.err == r.err and r.err >= b0), sum(1 for r in const if r.cls in UNSTABLE))
        out.append((scene, items, b0, const_fig))
    return out


def box_text(d):
    """(d)'s baseline in words: the host's bounding box against the grid, over the places where both ran."""
    boxes = [(x.box, x.precision) for x in d.effects if getattr(x, "box", None)]
    if not boxes:
        return ""
    return "%s to %s of its time, precision %s to %s (grid %s to %s)" % (
        g(min(b[0][0] for b in boxes), 2), g(max(b[0][0] for b in boxes), 2),
        g(min(b[0][1] for b in boxes), 2), g(max(b[0][1] for b in boxes), 2),
        g(min(b[1] for b in boxes), 2), g(max(b[1] for b in boxes), 2))


def realtime_line(data):
    """One line from realtime_grid.csv: per scene the wall seconds per simulated second (one thread)
    and the error of the exact method at the chosen implicit step (the largest within 1.5x of its
    explicit error), beside the explicit step at 0.9 dt_crit (the scene's dt where the grid has none);
    None without the file."""
    rows = data.csv("realtime_grid.csv")
    fig = lambda r: "%s (%s)" % (g(reader.num(r["wall_per_sim_s"]), 3), g(reader.num(r["pos_err_max_mm"]), 2))  # noqa: E731
    parts = []
    for scene in SCENES:
        sr = [r for r in rows if r.get("scene") == scene]
        chosen = next((r for r in sr if r.get("chosen") == "yes"), None)
        expl = next((r for r in sr if str(r.get("point")).startswith("explicit")),
                    next((r for r in sr if r.get("point") == "baseline"), None))
        crit = str(expl.get("point")).startswith("explicit") if expl else False
        bits = (["implicit %s ms %s" % (g(1e3 * reader.num(chosen["dt"]), 2), fig(chosen))] if chosen else []) + \
               (["explicit%s %s" % ("" if crit else " (scene dt)", fig(expl))] if expl else [])
        if bits:
            parts.append("%s %s" % (scene, ", ".join(bits)))
    if not parts:
        return None
    return ("- **Real time**, wall s per simulated s (error mm; CGAL, one thread, explicit at 0.9 dt_crit): "
            "%s." % "; ".join(parts))


def machines(rows):
    """The machines rows were measured on (their `machine` column)."""
    return sorted({str(r["machine"]) for r in rows if isinstance(r.get("machine"), str) and r["machine"]})


def works_line(cost):
    """What the paper's model does, in words, from the cost lines: the share of the error without
    contact force its best setting removes per scene, and where CGAL at its best ends and at
    what time against it; None where a scene lacks either."""
    gains, cgal, times = [], [], []
    for scene, items, base, _const in cost:
        pm = dict((label, run) for label, run, _n, _nf in items)
        paper, exact = pm.get("paper's model"), pm.get("CGAL")
        if paper is None or exact is None or not base == base or base <= 0:
            return None
        gains.append(g(100 * (base - paper.err) / base, 2))
        cgal.append(exact.err)
        times.append(exact.t / paper.t)
    if not gains:
        return None
    return ("Its best removes %s %% of the no-force error; CGAL at its best: %s to %s mm, %s to "
            "%s times its time." % (
                "/".join(gains), g(min(cgal), 2), g(max(cgal), 2), g(min(times), 2), g(max(times), 2)))


def summary_md(results, cost, counted, data=None):
    judged, distinct = counted
    lines = ["# What the data say", "",
             "<!-- generated by %s; do not edit -->" % MADE_BY, "",
             "Claims: comparisons declared beforehand; intervals: the window's range plus the reference's "
             "floor; failures lose ([claims.md](claims.md)).", "",
             "| claim | verdict | effect [interval] | holds | fails/straddles |", "|---|---|---|---|---|"]
    for res, revs in results:
        lines.append("| (%s) %s | %s | %s | %s | %s |" % (
            res.key, res.title, stated(res, revs), effect_cell(res), places(res.holds()),
            places(res.fails() + res.straddles())))
    by = {r.key: r for r, _ in results}
    d, e = by["d"], by["e"]
    dv = [x.value for x in d.effects if x.value == x.value]
    rec = [x.recall for x in d.effects if getattr(x, "recall", None) == getattr(x, "recall", None)]
    ev = [x.value for x in e.effects]
    lines += ["", "## The paper's model", ""]
    if dv:
        lines.append("- **Detection.** The grid takes 1/%s to 1/%s of the fastest exact detector's time, recall %s "
                     "to %s (d); over the host's box, %s to %s of the penetrating nodes under "
                     "%d deformations (e)." % (
                         g(min(dv), 2), g(max(dv), 3), g(min(rec)), g(max(rec)), g(min(ev)), g(max(ev)), len(ev)))
        box = box_text(d)
        if box:
            lines[-1] += " The host's box: %s." % box
    parts = ["%s %d/%d/%d" % (scene, through, farther, unstable)
             for scene, _i, _base, (n, through, farther, unstable) in cost]
    sizes = sorted({n for _s, _i, _b, (n, _t, _f, _u) in cost})
    lines.append("- **Constant forces** (%s per scene, line, plane; through/no closer than no force/"
                 "unstable): %s." % ("/".join(str(n) for n in sizes), "; ".join(parts)))
    works = works_line(cost)
    if works:
        lines[-1] += " " + works
    lines += ["", "## What accuracy costs", "",
              "Per scene and method, its fastest setting tied with its best (one-sided, not failing): "
              "error [interval] mm, µs per step%s." % (
                  " (%s)" % ", ".join(machines(data.csv("accuracy_time.csv"))) if data is not None else ""), ""]
    for scene, items, base, _const in cost:
        parts = []
        for label, run, n, nf in items:
            if run is None:
                parts.append("%s: all %d fail" % (label, n) if n else "%s: not run" % label)
            else:
                parts.append("%s %s [%s, %s], %s" % (label, g(run.err), g(run.err_lo, 2), g(run.err_hi, 2), g(run.t)))
        beside = ["%s %d" % (label, run.host_beside) for label, run, _n, _nf in items
                  if run is not None and run.host_beside > 0]
        lines.append("- **%s** (no force %s): %s%s." % (scene, g(base), "; ".join(parts),
                                                       " (host nodes through: %s)" % ", ".join(beside) if beside else ""))
    rt = realtime_line(data) if data is not None else None
    if rt:
        lines.append(rt)
    lines += ["", "Fragile: a defensible specification ([specifications.csv](specifications.csv): %d distinct; "
              "claims.md names it) reverses it. Times: within one session." % distinct, ""]
    return "\n".join(lines)


def claim_md(res, judged, specs, revs):
    out = ["## (%s) %s: %s" % (res.key, res.title, stated(res, revs)), "",
           "- Paper: %s." % res.paper,
           "- Declared: %s." % res.declared, "",
           "| where | effect [interval] | outcome | what |", "|---|---|---|---|"]
    for e in res.effects:
        out.append("| %s | %s | %s | %s |" % (e.where, e.interval(), e.outcome, e.note))
    if not res.effects:
        out.append("| - | - | not tested | nothing to compare |")
    out.append("")
    if res.extra.get("pairs") is not None:
        out.append("Setting by setting (the same voxel, force and regime with both rules): %s. Runs that fail: "
                   "line %d of %d, plane %d of %d." % (pairs_text(res), res.extra["fails"]["line"],
                                                      res.extra["counts"]["line"], res.extra["fails"]["plane"],
                                                      res.extra["counts"]["plane"]))
        out.append("")
    if res.extra.get("dropped"):
        out.append("Not timed (a failing run's time is no cost): %s." % "; ".join(res.extra["dropped"]))
        out.append("")
    if res.runs:
        why = {}
        for _grp, r in res.runs:
            k = r.failed.split(" (")[0] if r.failed else "does not fail"
            k = "nodes through" if k.endswith("nodes through") else k
            why[k] = why.get(k, 0) + 1
        beside = [r for _g, r in res.runs if r.host_beside > 0]
        out.append("Runs read: %d; %s. Stability class from %s.%s" % (
            len(res.runs), ", ".join("%s %d" % kv for kv in sorted(why.items())),
            " and ".join(sorted({r.cls_from for _g, r in res.runs})),
            (" One-sided runs with host nodes through the guest (reported, not a failure): %d (%s)." % (
                len(beside), ", ".join("%s: %d" % (r.label, r.host_beside) for r in beside[:4]) +
                (", ..." if len(beside) > 4 else ""))) if beside else ""))
        out.append("")
    names = REACHES[res.key]
    if names:
        vs = {}
        for _s, r in specs:
            vs[r.verdict] = vs.get(r.verdict, 0) + 1
        out.append("Specifications: %d judged over %s; %d distinct, their verdicts %s." % (
            judged, ", ".join(names), len(specs), ", ".join("%s %d" % kv for kv in sorted(vs.items()))))
        if revs:
            out.append("Reversed under: %s." % "; ".join("%s (%s)" % (s.name(), w) for s, w in revs[:3]) +
                       (" And %d more." % (len(revs) - 3) if len(revs) > 3 else ""))
    else:
        out.append("Specifications: no remaining choice reaches this claim's comparisons.")
    out.append("")
    return out


def pairs_text(res):
    """(a)'s settings in words: won by the other rule's failure, by the errors, or both failing."""
    ps = res.extra["pairs"]
    by_fail = [e for e in ps if e.value != e.value]
    by_err = [e for e in ps if e.value == e.value]
    n = lambda es, o: sum(1 for e in es if e.outcome == o)  # noqa: E731
    return ("the other rule fails in %d (the plane wins %d, the line %d); both hold in %d (the plane's error "
            "smaller in %d, the line's in %d, neither beyond the intervals in %d); both fail in %d" % (
                len(by_fail), n(by_fail, FOR), n(by_fail, AGAINST), len(by_err), n(by_err, FOR), n(by_err, AGAINST),
                n(by_err, "straddles"), res.extra["both_fail"]))


def class_coverage(data):
    """The limits paragraph's first sentences: per study file the claims read, how many rows carry the
    run's C++ class and how many the figures it was decided on (measure.run_class), from the rows."""
    parts, old = [], []
    for name in sorted(k for k in data._csv if isinstance(k, str)):
        rows = [r for r in data._csv[name] if reader.present(r.get("scene"))]
        if not rows or name == "ensembles.csv":
            continue
        cls = sum(1 for r in rows if reader.present(r.get("stability_class")))
        fig = sum(1 for r in rows if isinstance(r.get("chatter_length_from"), str) and r.get("chatter_length_from"))
        if cls == 0:
            old.append(name)
        else:
            parts.append("%s %d of %d rows (the class's figures: %d)" % (name, cls, len(rows), fig))
    text = ("Limits. Rows that carry the run's C++ stability class: %s; where a row carries the figures the class "
            "was decided on, the chatter length and the injection share are choices of the specification. "
            % ("; ".join(parts) if parts else "none"))
    if old:
        text += ("%s were run before the class, so their class is read from the error's motion over the "
                 "window. " % ", ".join(old))
    return text + "Only the runs of results/ensembles.csv carry an ensemble's spread over node orders."


def claims_md(results_specs, counted, data=None):
    out = ["# The paper's claims, tested", "",
           "<!-- generated by %s; do not edit. The answer first: SUMMARY.md -->" % MADE_BY, "",
           "How to read it. Each claim declares its comparisons before the data (scripts/harness_results/"
           "judge/claims.py). An effect is for the claim when its interval lies beyond the threshold on the "
           "claimed side, against when on the other, straddles when it contains it. A claim is supported "
           "when every effect is for it, not supported when every one is against (a claim about every case, "
           "as (e), when one is), inconclusive otherwise.", "",
           "A run fails when it blows up, lets a node through (a guest node; a host node too for a method "
           "that acts both ways, reported beside a one-sided one) or is unstable, and a failing run loses to "
           "one that does not. An error's interval is its range over the final window widened by the "
           "reference's floor; a time's is the range over the repeats. The choices left and their "
           "alternatives are in judge/choices.py: %d specifications judged, %d distinct." % counted, "",
           class_coverage(data) if data is not None else "", ""]
    for res, judged, specs, revs in results_specs:
        out += claim_md(res, judged, specs, revs)
    return "\n".join(out)


def shortened(root):
    """The report's runs (results/runs/) that ran fewer steps than their scene file asks for (a
    --quick reproduction): their figures describe those runs only."""
    out = []
    for key, _scene, _title, _force, elim, path in runs.existing_runs(root):
        s = reader.load_summary(path)
        try:
            with open(reader.scene_file(s)) as fh:
                want = int(json.load(fh)["time"]["steps"])
        except (OSError, ValueError, KeyError, TypeError):
            continue
        if int(reader.steps_run(s)) < want:
            out.append(runs.run_name(key, elim))
    return out


def macros(results, short=()):
    m = [("RunsNote", "\\textbf{Warning: shortened runs (%s, reproduce.sh --quick): their figures are not "
                      "results.}" % writers.tex_escape(", ".join(short)) if short else "")]
    for res, revs in results:
        L = LETTER[res.key]
        m.append(("Claim%sVerdict" % L, stated(res, revs)))
        m.append(("Claim%sEffect" % L, effect_cell(res)))
        m.append(("Claim%sHolds" % L, places(res.holds())))
        m.append(("Claim%sFails" % L, places(res.fails() + res.straddles())))
        if res.extra.get("pairs") is not None:
            m.append(("Claim%sPairs" % L, pairs_text(res)))
        if res.key == "d":
            m.append(("ClaimDBox", box_text(res) or "was not timed"))
    return m


def tex_macros(pairs):
    return "%% generated by %s; do not edit\n" % MADE_BY + "".join(
        "\\newcommand{\\%s}{%s}\n" % (k, v if v.startswith("\\") else writers.tex_escape(v)) for k, v in pairs)


def verdicts_tex(results):
    rows = ["\\begin{tabular}{p{0.30\\textwidth}p{0.14\\textwidth}p{0.22\\textwidth}p{0.24\\textwidth}}",
            "\\toprule", "claim & verdict & effect [interval] & fails or straddles \\\\", "\\midrule"]
    for res, revs in results:
        rows.append(" & ".join(writers.tex_escape(c) for c in (
            "(%s) %s" % (res.key, res.title), stated(res, revs), effect_cell(res),
            places(res.fails() + res.straddles()))) + " \\\\")
    rows += ["\\bottomrule", "\\end{tabular}", ""]
    return "\n".join(rows)


def write_specifications(path, all_specs):
    """One row per claim and distinct specification: the choices that reach the claim, its verdict
    and its effects."""
    cols = ["claim"] + [c.name for c in choices.CHOICES] + ["verdict", "effects"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for key, specs in all_specs:
            for spec, res in specs:
                w.writerow([key] + [spec.values[c.name] if c.name in REACHES[key] else "" for c in choices.CHOICES] +
                           [res.verdict, "; ".join("%s %s %s" % (e.where, e.interval(), e.outcome) for e in res.effects)])


def write_all(root):
    data = Data(root)
    results_specs, all_specs = [], []
    judged_total = 0
    for claim in ORDER:
        judged, specs = specifications(data, claim)
        revs = reversals(specs)
        results_specs.append((specs[0][1], judged, specs, revs))
        all_specs.append((specs[0][1].key, specs))
        judged_total += judged
    counted = (judged_total, sum(len(s) for _k, s in all_specs))
    results = [(r, revs) for r, _j, _s, revs in results_specs]
    cost = cost_lines(data, choices.DEFAULT)
    writers.write_text(os.path.join(root, "SUMMARY.md"), summary_md(results, cost, counted, data))
    short = shortened(root)
    text = claims_md(results_specs, counted, data)
    if short:
        text = text.replace("\n\n", "\n\n**Shortened runs** (%s): their figures are not results.\n\n" % ", ".join(short), 1)
    writers.write_text(os.path.join(root, "claims.md"), text)
    write_specifications(os.path.join(root, "specifications.csv"), all_specs)
    tables = os.path.join(root, "tables")
    os.makedirs(tables, exist_ok=True)
    from .claims import claim_c
    by = {r.key: r for r, _ in results}
    extra = [("ClaimCNoBound", effect_cell(claim_c(data, choices.Spec(restriction_bound="not required")))),
             ("ClaimBWhy", "; ".join("%s %s" % (e.where, getattr(e, "why", "") or "meets it") for e in by["b"].effects))]
    writers.write_text(os.path.join(tables, "claims_macros.tex"), tex_macros(macros(results, short) + extra))
    writers.write_text(os.path.join(tables, "claims_verdicts.tex"), verdicts_tex(results))
    return results
