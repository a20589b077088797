"""The written rules of the studies, stated once (scripts/study.py prints this text
in its --help), each implemented below and tested in tests/scripts/.

Definitions:
  window        the final time.window steps of a run (default 1000), after every driver, load and
                pressure ramp has finished (core/run/window.hpp); every run is measured by CGAL every
                STUDY_EVERY = 10 steps (one sampling rule for runs, sweeps and studies).
  error         against the scene's reference of the method's kind (core/run/compare.hpp; OF_ITS_KIND): a
                one-sided method (the guest's nodes pushed out of the host only, as the paper's model)
                against the one-sided reference (harness reference --one-sided: the limit it converges
                to), a method both ways against the two-sided one; the error against the other kind is
                measured beside it (--compare-also) and shown, with the two references' distance (what
                one-sidedness alone costs); so are the ablation's, convergence's, orientation's and
                regime's rows (the paper's model: one-sided); the swap (and the regime's swapped runs),
                restriction and region studies are against the two-sided reference (scripts say why),
                and so is the real-time study (it measured no other: the paper's one-sided model's
                error there includes its one-sidedness, as its section says). Over the window: pos_err_max (largest
                distance of a surface vertex from where the reference has it) as its window mean, with
                its window maximum and chatter amplitude (max - min); gap_max (largest gap where the
                reference has contact) window mean; depth_max (deepest node inside the other body)
                window maximum, and its peak over the whole run; tunnelled nodes (through the other
                body) window maximum.
  stable        (the studies' tables, the defaults and the front) the run's C++ stability class
                (summary.json stability_verdict, core/run/window.hpp: settled, steady, chatters,
                injects, grows, forced; docs/outputs.md, "Stability verdicts"): stable when it finished
                within the guard and its class is settled or steady. Rows made before that class
                (the committed studies without a stability_class column) keep the class they were
                written with, by the contact's power against the power put in (rho), which their tables
                say; rerunning a study replaces it.
  time          microseconds per step of detection plus elimination (t_contact) and of the whole
                step (t_step): the median over the run's steps, then the median over --repeats runs
                (the spread is the range over the runs).
  rule          (the defaults) among the stable settings that help: pos_err_max at most 90 % of the run
                without contact force's, or depth_max at most 90 % of its depth with pos_err_max no
                larger than its (a default must do something, and removing penetration by holding
                the bodies farther from the reference than no force does not count); the smallest pos_err_max; among
                those within 10 % of it, the smallest gap_max; among those, the fastest. None such:
                no default (and no CI threshold) for that scenario, said in ablation.md.
  front         the Pareto front of error (pos_err_max) against time (t_contact) over the evidence (below):
                a run is off it when another is no worse on both and better beyond the noise (below)
                on one. Two runs within the noise of each other on both do not put each other off;
                either can still be put off by a third (the noise is not transitive).
  noise         (the front) two runs' figures differ only by more than the larger of: 10 % of the
                larger figure (tie: judge/choices.py TABLE_CHOICES, with every other threshold of
                these rules), the sum of the two runs' chatter amplitudes over the window
                (position error), and the floor of the reference they are measured against
                (reader.reference_floor). Times differ only when their ranges over the repeats do not
                overlap.
  evidence      (the front) a run is on the front's footing only when it is stable, it helps (at least
                10 % closer to the reference than the same scene with no contact force,
                results/accuracy_time.csv's "no contact force" row; or 10 % shallower and no farther)
                and it tunnels nothing over the window.
The claims are judged apart, by scripts/harness_results/judge/ (scripts/claims.py).
"""

import math
import os

from . import reader
from .reference_kind import OF_ITS_KIND, KindFloor, as_two_sided, same_kind_base  # noqa: F401 (re-exported)
from .loading_period import forcing_end, forcing_end_of, scene_window  # noqa: F401
from .judge.choices import WRITTEN, TableRules  # noqa: F401 (the tables' rules; TableRules re-exported)
from .judge.measure import nodes_through

STABLE, UNSTABLE, FAILED = "stable", "unstable", "failed"
# The C++ classes a stable run has (the others: chatters, injects, grows; forced: still loaded).
STABLE_CLASSES = ("settled", "steady")
INCONCLUSIVE = "inconclusive"
# The accuracy study's baseline configuration: contact detected, never pushed (the run a setting
# must beat to help).
NO_FORCE = "no contact force"


# ---------------------------------------------------------------------------------------------
# Stability of one run
def stability_fields(s):
    """The stability columns of a study's row from a run's summary (stable above): stable (yes/no),
    stability and stability_class (the C++ class; "failed" when the run did not end ok, whatever
    class its window had),
    why_unstable (why it is not stable, "" when it is)."""
    x = reader.stability_inputs(s)
    cls = x["verdict"] or ""
    if x["status"] != "ok":
        if x["status"] == "refused":  # runner.harness: the harness refused the configuration (exit 2)
            why = "refused: %s" % x["error"]
        else:
            why = "not finite" if x["finite"] is False else str(x["status"])
        return {"stable": "no", "stability": FAILED, "stability_class": FAILED, "why_unstable": why}
    reasons = []
    if x["guard_violations"] > 0:
        reasons.append("dt above the limit")
    if cls not in STABLE_CLASSES:
        reasons.append(cls or "no stability class")
    return {"stable": "no" if reasons else "yes", "stability": cls or UNSTABLE, "stability_class": cls,
            "why_unstable": "; ".join(reasons)}


def is_stable(row):
    """A study's row (CSV or figures) that the rule called stable (its `stable` column, else its
    class)."""
    if "stable" in row:
        return row.get("stable") == "yes"
    return row.get("stability") in STABLE_CLASSES + (STABLE,)


def stability_source(rows):
    """How a table's rows were judged stable, in words: by the C++ class where the rows record it
    (column stability_class), else by the rule the committed rows were written with before it."""
    have = sum(1 for r in rows if reader.present(r.get("stability_class")))
    cls = ("the run's C++ stability class (settled or steady: stable; chatters, injects, grows or forced: not; "
           "core/run/window.hpp)")
    old = ("the rule these rows were written with, before the C++ class: the contact's power over the window "
           "against the power put in over the loading period (rho), stable when settled or at most 0.01, "
           "unstable above 0.04, marginal (not stable) between; rerunning the study gives them the class")
    if have == len(rows):
        return cls
    if have == 0:
        return old
    return "%s for the %d rows that record it; for the other %d, %s" % (cls, have, len(rows) - have, old)


def evidence_gap(row, rule=WRITTEN):
    """Why a row is not evidence (evidence above): "not stable", "tunnels", "no better than no
    force"; None when it is. A row that does not record tunnelling or helping is not held to it."""
    if not is_stable(row):
        return NOT_STABLE
    if nodes_through(row)[0] > rule.tunnel_limit:  # a one-sided method's host nodes through: beside
        return TUNNELS
    if row.get("helps") == "no":
        return NO_HELP
    return None


def is_evidence(row, rule=WRITTEN):
    """A row the front may rest on (evidence above)."""
    return evidence_gap(row, rule) is None


# ---------------------------------------------------------------------------------------------
# The defaults and the front
def useful(r, base, rule=WRITTEN):
    """At least 10 % closer to the reference than the run without contact force in position, or
    at least 10 % shallower in depth without being farther from the reference in position (a
    setting that removes penetration by holding the bodies apart, farther from where the reference
    has them than doing nothing, is not useful: depth alone would reward that wrong answer)."""
    u = rule.helps
    base = same_kind_base(r, base)  # the no-force run against the same kind of reference as r
    return (r["pos_err_max_mm"] <= u * base["pos_err_max_mm"]
            or (r["depth_max_mm"] <= u * base["depth_max_mm"]
                and r["pos_err_max_mm"] <= base["pos_err_max_mm"]))


def choose(rows, baseline=None, rule=WRITTEN):
    """The written rule (rule above) over stable rows; None when none is stable (or, given the
    run without contact force, when no stable row is clearly closer to the reference than it)."""
    ok = [r for r in rows if r["stable"] == "yes" and not math.isnan(r["pos_err_max_mm"])]
    if baseline is not None:
        ok = [r for r in ok if useful(r, baseline, rule)]
    if not ok:
        return None
    best = min(r["pos_err_max_mm"] for r in ok)
    near = [r for r in ok if r["pos_err_max_mm"] <= rule.within * best]
    gaps = [r["gap_max_mm"] for r in near if not math.isnan(r["gap_max_mm"])]
    if gaps:  # a row without a gap figure (no contact in the reference's sense) is not tied out by gap
        g = min(gaps)
        near = [r for r in near if math.isnan(r["gap_max_mm"]) or r["gap_max_mm"] <= rule.within * g + 1e-9]
    return min(near, key=lambda r: r["t_contact_us"])


def no_force_bases(root):
    """{scene: its run without contact force}: the NO_FORCE rows of accuracy_time.csv in the results
    folder `root`, what "helps" is judged against ({} without the file)."""
    rows = reader.read_csv(os.path.join(root, "accuracy_time.csv"), text=reader.STUDY_TEXT, missing=[])
    return {r["scene"]: as_two_sided(r) for r in rows if r.get("config") == NO_FORCE}


def helps_word(row, base, rule=WRITTEN):
    """"yes" when the row helps against `base` (useful: the scene's run without contact force),
    "no" when it does not or is that run itself (config NO_FORCE), "" when it cannot be told: no
    base, no position error, or no depth where only the depth could make it help."""
    if base is None or not reader.present(row.get("pos_err_max_mm")):
        return ""
    if row.get("config") == NO_FORCE:
        return "no"
    base = same_kind_base(row, base)  # (useful maps it too; the depth route below reads it)
    fig = {k: reader.num(row.get(k), math.nan) for k in ("pos_err_max_mm", "depth_max_mm")}
    fig["reference"] = row.get("reference")
    if useful(fig, base, rule):
        return "yes"
    if math.isnan(fig["depth_max_mm"]) and fig["pos_err_max_mm"] <= reader.num(base.get("pos_err_max_mm"), math.nan):
        return ""  # the depth route is open and the row has no depth to take it
    return "no"


def useless_text(row, rule=WRITTEN):
    """What makes a run useless whatever its stability, as the tables print it beside the stability:
    TUNNELS (more nodes through the other body than the rule allows: its `tunnelled` column, the
    guest's alone for a one-sided method whose row records them by body, judge/measure.nodes_through) and
    NO_HELP (its `helps` column is "no"), joined by "; "; "" when neither is known to hold."""
    words = []
    if nodes_through(row)[0] > rule.tunnel_limit:
        words.append(TUNNELS)
    if row.get("helps") == "no":
        words.append(NO_HELP)
    return "; ".join(words)


def two_sided_row(row, base, rule=WRITTEN):
    """`row` on its two-sided error (as_two_sided) with its helps judged again there against `base`
    (the scene's run without contact force; its helps as recorded without one); `row` itself where
    it is two-sided already or records no two-sided error."""
    two = as_two_sided(row)
    if two is row or base is None:
        return two
    return dict(two, helps=helps_word(two, base, rule))


def mark_useless(rows, bases, rule=WRITTEN):
    """Give every row its `helps` (helps_word against bases[its scene]) and `useless` (useless_text)
    columns; a run without contact force (config NO_FORCE, or force "F=0": detection alone) reads
    "baseline" (it is what helping is judged against). `bases`: {scene: {pos_err_max_mm,
    depth_max_mm}}. Returns rows."""
    for r in rows:
        if r.get("config") == NO_FORCE or r.get("force") == "F=0":
            r["helps"], r["useless"] = "", "baseline"
            continue
        r["helps"] = helps_word(r, bases.get(r.get("scene")), rule)
        r["useless"] = useless_text(r, rule)
    return rows


def pareto(rows, floor=0.0, x="t_contact", y="pos_err_max_mm", rule=WRITTEN):
    """The front of error (`y`) against time (`x`_us, with `x`_min_us / `x`_max_us the range over
    repeats) over the rows that are evidence (is_evidence: stable, nothing tunnelled beyond the
    limit, not "no better than no force"). A row is beaten by another that is no worse on both
    axes and better beyond the noise on one: error by decide (the noise: relative tie, the two
    chatters, the reference's `floor` in mm), time by time_decide (medians apart and ranges
    disjoint). Two rows within the noise of each other on both axes do not beat each other, but a
    third row may beat one of them and not the other: the tie is not transitive."""
    ok = [r for r in rows if is_evidence(r, rule) and reader.present(r.get(x + "_us")) and reader.present(r.get(y))]

    def beats(o, r):
        e, t = decide(o, r, y, floor, rule), time_decide(o, r, x)
        return e in ("a", WITHIN_NOISE) and t in ("a", WITHIN_NOISE) and "a" in (e, t)
    return [r for r in ok if not any(o is not r and beats(o, r) for o in ok)]


# ---------------------------------------------------------------------------------------------
# Statistics the rules use
def median(v):
    """Median of the values that are not NaN (NaN when none is)."""
    s = sorted(x for x in v if not (isinstance(x, float) and math.isnan(x)))
    if not s:
        return float("nan")
    n = len(s)
    return s[n // 2] if n % 2 else 0.5 * (s[n // 2 - 1] + s[n // 2])


def nearest_rank(sorted_vals, q):
    """Nearest-rank percentile q in (0, 100] of an ascending list (an observed value)."""
    if not sorted_vals:
        return None
    k = max(1, int(math.ceil(q / 100.0 * len(sorted_vals))))
    return sorted_vals[k - 1]


# ---------------------------------------------------------------------------------------------
# Comparisons beyond the noise (the front)
WITHIN_NOISE, NOT_STABLE, MISSING = "within noise", "not stable", "missing"
TUNNELS, NO_HELP = "tunnels", "no better than no force"


def noise(a, b, key="pos_err_max_mm", floor=0.0, rule=WRITTEN):
    """How far apart two rows' figures `key` must be to differ (noise above): the largest of `tie`
    times the larger figure, the two rows' chatter amplitudes summed (pos_err_amp_mm; position
    error only) and the floor of the reference they are measured against (same unit as the figure;
    a KindFloor: the larger of the two rows' references' floors)."""
    tie = rule.tie
    if isinstance(floor, KindFloor):
        floor = floor.of(a, b)
    amp = 0.0
    if key == "pos_err_max_mm":
        amp = reader.num(a.get("pos_err_amp_mm"), 0.0) + reader.num(b.get("pos_err_amp_mm"), 0.0)
    return max(tie * max(a[key], b[key]), amp, reader.num(floor, 0.0))


def decide(a, b, key="pos_err_max_mm", floor=0.0, rule=WRITTEN):
    """Two rows by `key`, smaller better (comparison above): "a", "b", WITHIN_NOISE, or why it is not
    judged (evidence_gap of either row: NOT_STABLE, TUNNELS, NO_HELP; MISSING)."""
    gap = evidence_gap(a, rule) or evidence_gap(b, rule)
    if gap:
        return gap
    if not (reader.present(a.get(key)) and reader.present(b.get(key))):
        return MISSING
    m = noise(a, b, key, floor, rule)
    if a[key] + m < b[key]:
        return "a"
    if b[key] + m < a[key]:
        return "b"
    return WITHIN_NOISE


def time_decide(a, b, key="t_contact", factor=1.0):
    """Two rows by time (`key`_us median, `key`_min_us / `key`_max_us the range over repeats): "a"
    when a is faster by more than `factor` (its median times factor below b's) and a's slowest run is
    faster than b's fastest; "b" the other way; WITHIN_NOISE otherwise; MISSING without times."""
    ta, tb = a.get(key + "_us"), b.get(key + "_us")
    if not (reader.present(ta) and reader.present(tb)):
        return MISSING
    amax, amin = reader.num(a.get(key + "_max_us"), ta), reader.num(a.get(key + "_min_us"), ta)
    bmax, bmin = reader.num(b.get(key + "_max_us"), tb), reader.num(b.get(key + "_min_us"), tb)
    if ta * factor < tb and amax < bmin:
        return "a"
    if tb * factor < ta and bmax < amin:
        return "b"
    return WITHIN_NOISE
