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
  stable        (the studies' tables, the defaults and the front, as the committed study files
                record it) by the run's contact power over the window against the power the scene
                put in over its loading period (rho, summary.json window.contact_power_ratio) with a
                margin of a factor 2 either way around 0.02: stable when the run settled or chatters
                with rho <= 0.01; unstable when rho > 0.04, when its kinetic energy grows over the
                window, when contact kicked the bodies, when dt exceeded the guard or the state went
                non-finite; marginal in between. The claims do not use it: the judge reads a run's
                C++ stability class (core/run/window.hpp) or, for rows made before it, the error's
                motion over the window (scripts/harness_results/judge/measure.py).
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
                larger figure (TIE), the sum of the two runs' chatter amplitudes over the window
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
import re

from . import reader
from .reference_kind import OF_ITS_KIND, KindFloor, as_two_sided, same_kind_base  # noqa: F401 (re-exported)
from .loading_period import forcing_end, forcing_end_of, scene_window  # noqa: F401

# Stability by the contact's power over the window against the power put in (core/run/window.hpp,
# whose own limit is INJECTION_LIMIT), with a margin of a factor MARGIN either way.
INJECTION_LIMIT = 0.02
MARGIN = 2.0
BALANCE = 0.01
STABLE, MARGINAL, UNSTABLE, FAILED = "stable", "marginal", "unstable", "failed"
# The defaults: rows within WITHIN of the best are tied; a default must be USEFUL: its position error
# or its depth at most this share of the run without contact force (contact detected, never pushed).
WITHIN = 1.10
USEFUL = 0.9
INCONCLUSIVE = "inconclusive"
# The accuracy study's baseline configuration: contact detected, never pushed (the run a setting
# must beat to help).
NO_FORCE = "no contact force"
# The front's relative tie (noise above).
TIE = 0.10


class Variant:
    """One choice of the studies' free parameters: marginal says whether the marginal band counts as
    stable, tie is the relative tie of the noise, tunnel_limit the nodes a run may tunnel over the
    window and still be on the front's footing, helps the share of the no-force run's figures at which
    a run helps (USEFUL)."""

    def __init__(self, marginal="unstable", tie=TIE, tunnel_limit=0, helps=USEFUL):
        self.marginal, self.tie, self.tunnel_limit, self.helps = marginal, tie, tunnel_limit, helps

    def name(self):
        """"marginal counted stable, tie 5 %": the choices that differ from the default."""
        parts = []
        if self.marginal != "unstable":
            parts.append("marginal counted %s" % self.marginal)
        if self.tie != TIE:
            parts.append("tie %g %%" % (100 * self.tie))
        if self.tunnel_limit:
            parts.append("up to %d tunnelled nodes" % self.tunnel_limit)
        if self.helps != USEFUL:
            parts.append("helps at %g %% of no force" % (100 * self.helps))
        return ", ".join(parts) or "the rule as written"


DEFAULT = Variant()
CURRENT = DEFAULT


class using:
    """with rules.using(variant): the rule's choices are the variant's inside the block."""

    def __init__(self, variant):
        self.variant = variant

    def __enter__(self):
        global CURRENT
        self.saved, CURRENT = CURRENT, self.variant
        return self.variant

    def __exit__(self, *exc):
        global CURRENT
        CURRENT = self.saved
        return False


# ---------------------------------------------------------------------------------------------
# Stability of one run
def classify(s):
    """(class, reasons) of one run's summary by the written rule (stable above): "stable",
    "marginal", "unstable" or "failed"."""
    x = reader.stability_inputs(s)
    rho, verdict = x["rho"], x["verdict"]
    if x["status"] != "ok":
        if x["status"] == "refused":  # runner.harness: the harness refused the configuration (exit 2)
            return FAILED, ["refused: %s" % x["error"]]
        return FAILED, ["not finite" if x["finite"] is False else str(x["status"])]
    reasons = []
    if x["guard_violations"] > 0:
        reasons.append("dt above the limit")
    if verdict == "grows":
        reasons.append("kinetic energy grows over the window (x%.3g)" % x["growth"])
    if x["kicked"]:
        reasons.append("contact kicked the bodies (net work %.3g J still held as motion)" % x["net_contact_work"])
    if abs(x["balance_error"]) > BALANCE:
        reasons.append("energy audit open")
    return judge_power(rho, verdict == "settled", reasons)


def judge_power(rho, settled, reasons):
    """(class, reasons) from the contact's power ratio rho under the current limits, given whether
    the run settled and its other reasons to be unstable (stable above): unstable with any reason or
    rho above the band, marginal within the band unless it settled, stable otherwise."""
    reasons = list(reasons)
    limit = INJECTION_LIMIT
    if not math.isnan(rho) and rho > limit * MARGIN:
        reasons.append("contact power %.3g of the power put in" % rho)
    if reasons:
        return UNSTABLE, reasons
    if not settled and not math.isnan(rho) and rho > limit / MARGIN:
        return MARGINAL, ["contact power %.3g of the power put in (within a factor %g of %g)" % (rho, MARGIN, limit)]
    return STABLE, []


def counts_stable(cls):
    """Whether a stability class counts as stable under the current rule (marginal: the variant's)."""
    return cls == STABLE or (cls == MARGINAL and CURRENT.marginal == "stable")


def reclassify_row(row):
    """A study row (CSV) judged again under the current rule from what it records: its class, its
    reasons (why_unstable), settled and rho (contact_power_ratio). Reasons other than the contact's
    power (dt, growth, a kick, the audit, a failure) stand; the power is judged against the current
    limits. A copy with stable, stability and why_unstable rewritten; rows without a stability
    column are returned as they are. Under the rule as written it reproduces the study's columns
    (tests/scripts/test_robustness.py)."""
    cls = row.get("stability")
    if cls in (None, "") or cls == FAILED:
        return row
    out = dict(row)
    if "why_unstable" not in row:  # nothing to judge again from (realtime.csv): the class stands
        if "stable" not in row or cls == MARGINAL:
            out["stable"] = "yes" if counts_stable(cls) else "no"
        return out
    said = [x for x in str(row.get("why_unstable") or "").split("; ") if x]
    reasons = [x for x in said if not x.startswith("contact power")]
    # rho: its column, else the figure its reason gives (a stable row of a file without the column
    # keeps an unknown rho: it stays stable under every limit, a limit of these files' variants)
    rho = reader.num(row.get("contact_power_ratio"))
    if math.isnan(rho):
        for x in said:
            m = re.match(r"contact power ([-+0-9.eE]+) of the power put in", x)
            if m:
                rho = float(m.group(1))
    if "settled" in row and str(row.get("settled")) not in ("", "nan"):
        settled = str(row.get("settled")) in ("True", "true", "yes", "1")
    else:  # not recorded: a stable row whose rho lies above the band was settled
        settled = cls == STABLE and not math.isnan(rho) and rho > INJECTION_LIMIT / MARGIN
    new, reasons = judge_power(rho, settled, reasons)
    out["stability"], out["why_unstable"] = new, "; ".join(reasons)
    out["stable"] = "yes" if counts_stable(new) else "no"
    return out


def stability_fields(s):
    """The stability columns of a study's row: stable (yes/no), stability (the class), why_unstable."""
    cls, reasons = classify(s)
    return {"stable": "yes" if counts_stable(cls) else "no", "stability": cls, "why_unstable": "; ".join(reasons)}


def is_stable(row):
    """A study's row (CSV or figures) that the rule called stable (its `stable` column, else its
    class under the current rule)."""
    if "stable" in row:
        return row.get("stable") == "yes"
    return counts_stable(row.get("stability"))


def evidence_gap(row):
    """Why a row is not evidence (evidence above): "not stable", "tunnels", "no better than no
    force"; None when it is. A row that does not record tunnelling or helping is not held to it."""
    if not is_stable(row):
        return NOT_STABLE
    if reader.num(row.get("tunnelled"), 0.0) > CURRENT.tunnel_limit:
        return TUNNELS
    if row.get("helps") == "no":
        return NO_HELP
    return None


def is_evidence(row):
    """A row that a claim may rest on (evidence above)."""
    return evidence_gap(row) is None


# ---------------------------------------------------------------------------------------------
# The defaults and the front
def useful(r, base, share=None):
    """At least 10 % closer to the reference than the run without contact force in position, or
    at least 10 % shallower in depth without being farther from the reference in position (a
    setting that removes penetration by holding the bodies apart, farther from where the reference
    has them than doing nothing, is not useful: depth alone would reward that wrong answer)."""
    u = CURRENT.helps if share is None else share
    base = same_kind_base(r, base)  # the no-force run against the same kind of reference as r
    return (r["pos_err_max_mm"] <= u * base["pos_err_max_mm"]
            or (r["depth_max_mm"] <= u * base["depth_max_mm"]
                and r["pos_err_max_mm"] <= base["pos_err_max_mm"]))


def choose(rows, baseline=None):
    """The written rule (rule above) over stable rows; None when none is stable (or, given the
    run without contact force, when no stable row is clearly closer to the reference than it)."""
    ok = [r for r in rows if r["stable"] == "yes" and not math.isnan(r["pos_err_max_mm"])]
    if baseline is not None:
        ok = [r for r in ok if useful(r, baseline)]
    if not ok:
        return None
    best = min(r["pos_err_max_mm"] for r in ok)
    near = [r for r in ok if r["pos_err_max_mm"] <= WITHIN * best]
    gaps = [r["gap_max_mm"] for r in near if not math.isnan(r["gap_max_mm"])]
    if gaps:  # a row without a gap figure (no contact in the reference's sense) is not tied out by gap
        g = min(gaps)
        near = [r for r in near if math.isnan(r["gap_max_mm"]) or r["gap_max_mm"] <= WITHIN * g + 1e-9]
    return min(near, key=lambda r: r["t_contact_us"])


def no_force_bases(root):
    """{scene: its run without contact force}: the NO_FORCE rows of accuracy_time.csv in the results
    folder `root`, what "helps" is judged against ({} without the file)."""
    rows = reader.read_csv(os.path.join(root, "accuracy_time.csv"), text=reader.STUDY_TEXT, missing=[])
    return {r["scene"]: as_two_sided(r) for r in rows if r.get("config") == NO_FORCE}


def helps_word(row, base):
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
    if useful(fig, base):
        return "yes"
    if math.isnan(fig["depth_max_mm"]) and fig["pos_err_max_mm"] <= reader.num(base.get("pos_err_max_mm"), math.nan):
        return ""  # the depth route is open and the row has no depth to take it
    return "no"


def useless_text(row):
    """What makes a run useless whatever its stability, as the tables print it beside the stability:
    TUNNELS (more nodes through the other body than the rule allows, its `tunnelled` column) and
    NO_HELP (its `helps` column is "no"), joined by "; "; "" when neither is known to hold."""
    words = []
    if reader.num(row.get("tunnelled"), 0.0) > CURRENT.tunnel_limit:
        words.append(TUNNELS)
    if row.get("helps") == "no":
        words.append(NO_HELP)
    return "; ".join(words)


def two_sided_row(row, base):
    """`row` on its two-sided error (as_two_sided) with its helps judged again there against `base`
    (the scene's run without contact force; its helps as recorded without one); `row` itself where
    it is two-sided already or records no two-sided error."""
    two = as_two_sided(row)
    if two is row or base is None:
        return two
    return dict(two, helps=helps_word(two, base))


def mark_useless(rows, bases):
    """Give every row its `helps` (helps_word against bases[its scene]) and `useless` (useless_text)
    columns; a run without contact force (config NO_FORCE, or force "F=0": detection alone) reads
    "baseline" (it is what helping is judged against). `bases`: {scene: {pos_err_max_mm,
    depth_max_mm}}. Returns rows."""
    for r in rows:
        if r.get("config") == NO_FORCE or r.get("force") == "F=0":
            r["helps"], r["useless"] = "", "baseline"
            continue
        r["helps"] = helps_word(r, bases.get(r.get("scene")))
        r["useless"] = useless_text(r)
    return rows


def pareto(rows, floor=0.0, x="t_contact", y="pos_err_max_mm"):
    """The front of error (`y`) against time (`x`_us, with `x`_min_us / `x`_max_us the range over
    repeats) over the rows that are evidence (is_evidence: stable, nothing tunnelled beyond the
    limit, not "no better than no force"). A row is beaten by another that is no worse on both
    axes and better beyond the noise on one: error by decide (the noise: relative tie, the two
    chatters, the reference's `floor` in mm), time by time_decide (medians apart and ranges
    disjoint). Two rows within the noise of each other on both axes do not beat each other, but a
    third row may beat one of them and not the other: the tie is not transitive."""
    ok = [r for r in rows if is_evidence(r) and reader.present(r.get(x + "_us")) and reader.present(r.get(y))]

    def beats(o, r):
        e, t = decide(o, r, y, floor), time_decide(o, r, x)
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


def noise(a, b, key="pos_err_max_mm", floor=0.0, tie=None):
    """How far apart two rows' figures `key` must be to differ (noise above): the largest of `tie`
    times the larger figure, the two rows' chatter amplitudes summed (pos_err_amp_mm; position
    error only) and the floor of the reference they are measured against (same unit as the figure;
    a KindFloor: the larger of the two rows' references' floors)."""
    tie = CURRENT.tie if tie is None else tie
    if isinstance(floor, KindFloor):
        floor = floor.of(a, b)
    amp = 0.0
    if key == "pos_err_max_mm":
        amp = reader.num(a.get("pos_err_amp_mm"), 0.0) + reader.num(b.get("pos_err_amp_mm"), 0.0)
    return max(tie * max(a[key], b[key]), amp, reader.num(floor, 0.0))


def decide(a, b, key="pos_err_max_mm", floor=0.0, tie=None):
    """Two rows by `key`, smaller better (comparison above): "a", "b", WITHIN_NOISE, or why it is not
    judged (evidence_gap of either row: NOT_STABLE, TUNNELS, NO_HELP; MISSING)."""
    gap = evidence_gap(a) or evidence_gap(b)
    if gap:
        return gap
    if not (reader.present(a.get(key)) and reader.present(b.get(key))):
        return MISSING
    m = noise(a, b, key, floor, tie)
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
