"""Claim (b), section 5: "Sometimes separate points are in penetration but this is normal since
additional forces can eliminate collision during several iterations." Judged per run of
results/runs/ (the paper's voxel model on the bundled scenes) on its episodes of penetration
(penetration_episodes.csv: a node truly penetrating on consecutive measured steps), on guest nodes
and on host nodes separately. The paper's model keeps the guest's nodes out of the host and looks
up no host node: the claim is about the guest's nodes; the host's are shown beside it (a one-sided
model leaves them inside by design). The claim holds for a body's nodes in a run when:
  separate points   at most 5 % of the body's nodes penetrate at the peak (CGAL, measured steps);
  several steps     the 90th percentile of the episode length is at most 100 steps (5 ms);
  eliminated        at most 5 % of the episodes failed: still open when the run ends, or ended on
                    the far side of the other body (tunnelled: gone through, not eliminated).
An episode's passage is followed along the node's path between measured steps (CGAL), so a node that
goes through between two of them without being found inside makes a failed episode of its own. A run
that is not stable (rules.classify) is not judged. A run whose episodes do not record passages
(penetration_episodes.csv without `tunnelled`, runs before it) and whose nodes tunnelled over the
window is not judged when its episodes meet the criteria, and counts against when they fail them.
The claim is about the episodes a run shows, not its accuracy: helping (rules.py, evidence) is not
asked. Percentiles are nearest-rank; lengths are measured every references.every steps (10): an
episode that enters and leaves the same side between two measured steps is not seen (the limit of
the sampling; one that goes through is).
Writes tables/claims_b.tex.
"""

from .. import reader, rewindow, rules, writers
from ..reference_kind import of_its_kind
from .common import Verdict, exception_record, tally_macros, verdict_line

SEPARATE_MAX_FRACTION = 0.05
P90_MAX_STEPS = 100
OPEN_MAX_FRACTION = 0.05


def failing_criteria(peak_frac, p90, failed_frac, p90_max=P90_MAX_STEPS, failed_max=OPEN_MAX_FRACTION,
                     peak_max=SEPARATE_MAX_FRACTION, unit="steps"):
    """The criteria a body's episodes fail, in words ([] when all three hold): the peak share of its
    nodes, the 90th percentile length (in `unit`; none or NaN: not judged), the failed share."""
    reasons = []
    if peak_frac is not None and peak_frac == peak_frac and peak_frac > peak_max:
        reasons.append("peak %.1f %% of its nodes > %g %%" % (100 * peak_frac, 100 * peak_max))
    if p90 is not None and p90 == p90 and p90 > p90_max:
        reasons.append("p90 %s %s > %d" % ("%d" % p90 if isinstance(p90, int) else "%g" % p90, unit, p90_max))
    if failed_frac > failed_max:
        reasons.append("%.1f %% failed (open or through) > %g %%" % (100 * failed_frac, 100 * failed_max))
    return reasons


def episode_stats(episodes, body, nodes, peak):
    """The episodes of one body in one run against the three criteria."""
    lengths = sorted(int(r["steps"]) for r in episodes if r["body"] == body)
    n = len(lengths)
    nopen = sum(int(r["open"]) for r in episodes if r["body"] == body)
    nthrough = sum(int(r["tunnelled"]) for r in episodes if r["body"] == body)
    failed = sum(1 for r in episodes if r["body"] == body and (r["open"] or r["tunnelled"]))
    st = {"episodes": n, "median": rules.nearest_rank(lengths, 50), "p90": rules.nearest_rank(lengths, 90),
          "max": lengths[-1] if lengths else None, "open": nopen, "through": nthrough,
          "open_frac": (failed / n) if n else 0.0, "through_frac": (nthrough / n) if n else 0.0,
          "passages": any(r.get("passages") for r in episodes),
          "peak": peak, "peak_frac": (peak / nodes) if nodes else None}
    reasons = failing_criteria(st["peak_frac"], st["p90"], st["open_frac"])
    st["holds"] = not reasons
    st["why"] = "; ".join(reasons) if reasons else "all three met"
    return st


# The episodes' figures of a run by its folder: they do not depend on the rule (robustness.py judges
# the claims again under each of its variants; reading steps.csv is the slow part).
_FIGURES = {}


def run_figures(path):
    """(summary, guest stats, host stats) of the run in `path`, read once."""
    if path not in _FIGURES:
        s = reader.load_summary(path)
        host, guest = reader.contact_bodies(s, strict=False)
        cols = reader.load_steps(path)
        _, g = reader.measured(cols, "true_pen_guest")
        _, h = reader.measured(cols, "true_pen_host")
        ep = reader.load_episodes(path)
        gs = episode_stats(ep, guest, reader.body_nodes(s, guest), int(max(g, default=0)))
        gs["tunnelled"] = reader.num(reader.window_figures(s).get("tunnelled"), 0.0)
        _FIGURES[path] = (s, gs, episode_stats(ep, host, reader.body_nodes(s, host), int(max(h, default=0))))
    return _FIGURES[path]


_REWINDOWED = {}


def under_window(path, s):
    """The run's summary judged over the current rule's window (rules.Variant.window: the scene's
    time.window times it; rewindow.rewindow from its steps.csv), `s` itself at the scene's window."""
    f = rules.CURRENT.window
    if f == 1.0:
        return s
    if (path, f) not in _REWINDOWED:
        _REWINDOWED[(path, f)] = rewindow.rewindow(path, s, f)
    return _REWINDOWED[(path, f)]


def run_rows(ctx):
    """Per run: (title, eliminator, stability under the current rule, guest stats, host stats); the
    stability and the nodes tunnelled over the window are the current window's (under_window), the
    episodes are the whole run's."""
    out = []
    for key, _scene, title, _force, elim, path in ctx.runs:
        s, gs, hs = run_figures(path)
        sw = under_window(path, s)
        if sw is not s:
            gs = dict(gs, tunnelled=reader.num(reader.window_figures(sw).get("tunnelled"), 0.0))
        # whether it helps (the general evidence rule's third test; (b)'s own rule does not ask it):
        # against the reference of its kind, as the accuracy table says it
        k, kind = of_its_kind(sw)
        base = ctx.no_force(reader.scene(s))
        gs = dict(gs, helps=rules.helps_word(dict(reader.window_figures(k), reference=kind), base) if base else "")
        out.append((title, elim, rules.classify(sw)[0], gs, hs))
    return out


def outcome(stab, g):
    """For (a), against (b), or why the run is not judged: not stable; or, where its episodes do not
    record passages (older runs), its nodes went through while its episodes meet the criteria (an
    episode closed by tunnelling was not eliminated, so tunnelling could only make such a run pass:
    one that fails all the same counts against). Where they do, a tunnelled episode is a failed one
    and the run is judged as it is."""
    if not rules.counts_stable(stab):
        return rules.NOT_STABLE
    if g["holds"] and not g.get("passages") and g.get("tunnelled", 0) > rules.CURRENT.tunnel_limit:
        return rules.TUNNELS
    return "a" if g["holds"] else "b"


def general_outcome(stab, g):
    """outcome under the general evidence rule (rules.evidence_gap): a run that tunnelled over the
    window is not judged whatever its episodes (the claim's own rule judges it: its tunnelled
    episodes failed)."""
    o = outcome(stab, g)
    if o in ("a", "b") and g.get("tunnelled", 0) > rules.CURRENT.tunnel_limit:
        return rules.TUNNELS
    if o in ("a", "b") and g.get("helps") == "no":
        return rules.NO_HELP
    return o


EXCEPTION = ("runs that are not evidence by the general rule (nodes tunnelled over the window, or no better than no "
             "contact force), judged by (b)'s own rule (a stable run is judged on its episodes; a tunnelled episode "
             "failed: not eliminated)")


def judge(ctx):
    rows = run_rows(ctx)
    outcomes = [outcome(stab, g) for _t, _e, stab, g, _h in rows]
    verdict = rules.claim_verdict(outcomes, "a")
    rests = exception_record(outcomes, [general_outcome(stab, g) for _t, _e, stab, g, _h in rows], EXCEPTION)
    fmt = writers.fmt
    md = ["## (b) Penetrating points are few and eliminated within several iterations", "",
          "An episode: a node found truly penetrating on consecutive measured steps (every 10 steps); its length in "
          "steps from its first to its last measured step plus 10 (one seen once counts 10). Criteria per body: peak penetrating nodes <= %g %% of its nodes, 90th percentile of the episodes "
          "<= %d steps, failed (still penetrating at the end, or ended on the far side of the other body: gone "
          "through, not eliminated) <= %g %% of its episodes; a node that goes through between two measured steps "
          "makes a failed episode of its own. The claim is judged on the guest's nodes (the paper's model keeps those "
          "out); the host's are shown beside. A run that is not stable is not judged; where a run's episodes do not "
          "record passages (runs before that column), one whose nodes tunnelled over the window and whose episodes "
          "meet the criteria is not judged (they may have closed by passage) and one that fails them counts against "
          "(stability: its class, and the nodes tunnelled over the window when any). Sampling limit: an episode that "
          "enters and leaves the same side between two measured steps is not seen." % (
              100 * SEPARATE_MAX_FRACTION, P90_MAX_STEPS, 100 * OPEN_MAX_FRACTION), "",
          "| scenario | elim. | stability | nodes | episodes | median | p90 | failed (%) | of which through (%) | "
          "peak (% of nodes) | holds |",
          "|---|---|---|---|---:|---:|---:|---:|---:|---:|---|"]
    def stability(stab, g, h):
        """The run's class and the nodes tunnelled over the window (both bodies), split by body where
        the episodes record passages (each tunnelled node ends one through-episode)."""
        if g.get("tunnelled", 0) <= 0:
            return stab
        split = " (%d guest, %d host, by episode)" % (g["through"], h["through"]) if g["passages"] else ""
        return stab + ", %d tunnelled%s" % (g["tunnelled"], split)

    for title, elim, stab, g, h in rows:
        for who, st in (("guest", g), ("host", h)):
            md.append("| %s | %s | %s | %s | %d | %s | %s | %.1f | %s | %s | %s |" % (
                title, elim, stability(stab, g, h), who,
                st["episodes"], fmt(st["median"], "d"), fmt(st["p90"], "d"),
                100 * st["open_frac"], "%.1f" % (100 * st["through_frac"]) if st["passages"] else "-", fmt(None if st["peak_frac"] is None else 100 * st["peak_frac"], ".2f"),
                ("yes" if st["holds"] else "no: " + st["why"]) + ("" if who == "guest" else " (not the model's)")))
    md += ["", verdict_line("(b)", verdict, outcomes, rule="on the guest's nodes of each stable run (a tunnelled episode failed; older runs without passages: one that tunnelled judged only when it fails)"), ""]
    tex = ["%% generated by scripts/claims.py; do not edit\n",
           "\\begin{tabular}{lllrrrrrl}\n\\toprule\n",
           "scenario & elim. & nodes & episodes & median & p90 & failed (\\%) & peak (\\% nodes) & holds \\\\\n"
           "\\midrule\n"]
    prev = None
    for title, elim, stab, g, h in rows:
        if prev is not None and prev != title:
            tex.append("\\addlinespace\n")
        for who, st in (("guest", g), ("host", h)):
            tex.append("%s & %s & %s & %d & %s & %s & %.1f & %s & %s \\\\\n" % (
                writers.tex_escape(title) if (title != prev and who == "guest") else "", elim if who == "guest" else "",
                who, st["episodes"], fmt(st["median"], "d"), fmt(st["p90"], "d"), 100 * st["open_frac"],
                fmt(None if st["peak_frac"] is None else 100 * st["peak_frac"], ".2f"),
                ("yes" if st["holds"] else "no") if who == "guest" else "--"))
        prev = title
    tex.append("\\bottomrule\n\\end{tabular}\n")
    macros = tally_macros("ClaimB", verdict, outcomes) + [
        ("ClaimBRuns", str(len(rows))), ("ClaimBSepMax", "%g" % (100 * SEPARATE_MAX_FRACTION)),
        ("ClaimBPninetyMax", "%d" % P90_MAX_STEPS), ("ClaimBOpenMax", "%g" % (100 * OPEN_MAX_FRACTION)),
        ("ClaimBStableRuns", str(sum(1 for r in rows if r[2] == rules.STABLE)))]
    if rests:
        md.insert(-1, "**The claim's own rule:** %s." % rests["text"])
        md.insert(-1, "")
    return Verdict("b_episodes", verdict, md, macros, {"claims_b.tex": "".join(tex)}, data=rows,
                   rests={"ClaimB": rests} if rests else None)
