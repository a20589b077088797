"""The written rules of the studies and the claims, stated once (scripts/study.py prints this text
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
  stable        by the run's contact power over the window against the power the scene put in
                (over its loading period: every committed study file records it so, rho_norm "loading",
                and so do the report's runs; region.csv does not record its normalisation; robustness
                judges every verdict with rho over the whole time before the window too, the old
                normalisation with the limits as they were calibrated for it)
                (rho, summary.json window.contact_power_ratio; the harness calls a run "injects"
                above 0.02) with a stated margin of a factor 2 either way: stable when the run
                settled or chatters with rho <= 0.01; unstable when rho > 0.04, when its kinetic
                energy grows over the window, when contact kicked the bodies (its net work still
                held as motion), when dt exceeded the guard or the state went non-finite; marginal
                in between (0.01 < rho <= 0.04). A verdict that rests on a run that is not stable is
                "inconclusive". The energy audit must close within 1 % for the figures to count.
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
  noise         (claims) two runs' figures differ only by more than the larger of: 10 % of the larger
                figure, the sum of the two runs' chatter amplitudes over the window (position error),
                and the floor of the reference they are measured against (reader.reference_floor: its
                last level's change, or the largest of its last two when the loop is not asymptotic).
                The relative tie, argued: every run is deterministic (the same binary gives the same
                state hash), but not robust in its last digits: a rounding perturbation (the node
                order, docs/findings.md) moves a chattering run's rho from 0.016 to 0.028 and a
                tunnelling run's count from 1 to 3 nodes, and the harness has not measured that
                spread per configuration (no ensemble over node orders), nor what it does to the
                position error the tie is applied to; the tie stands in for it, an argument by
                analogy, not a measurement.
                It is a choice, not a measurement: robustness varies it (0, 5 and 10 %), and so the
                mesh floor (the sphere's reference on a refined mesh against its own, 1.13 mm, for a
                claim read as about the method rather than this mesh), and a verdict that either
                decides is stated fragile.
                Times differ only when their ranges over the repeats do not overlap.
  evidence      (claims) a run is evidence only when it is stable, it helps (the defaults' rule
                `useful`: at least 10 % closer to the reference than the same scene with no contact
                force, results/accuracy_time.csv's "no contact force" row; or 10 % shallower and no
                farther) and it tunnels nothing over the window (tunnelled = 0): a run that does
                nothing, or whose nodes went through, says nothing about how well a method works.
  comparison    (claims) two runs by a figure, smaller better: "a" or "b" when one is smaller by more
                than the noise, "within noise" otherwise; not judged when either run is not evidence
                ("not stable", "tunnels", "no better than no force") or a figure is missing. A
                comparison between two runs that are evidence is decisive (for, against or within
                the noise).
  verdict       (claims) over a claim's decisive comparisons D = for + against + within the noise:
                "inconclusive" when D < MIN_DECISIVE (3: one comparison, however clear, is one
                configuration, and the studies' grids are built to give a claim at least three);
                "mixed" when the comparisons for it and those against it are both more than MIXED_SHARE
                (20 %) of D (both present beyond the share: the configurations disagree);
                "supported" when the comparisons for it are at least 1 - MIXED_SHARE (80 %) of D;
                "not supported" when they are at most MIXED_SHARE (20 %) of D; "inconclusive" in
                between with nothing against beyond the share (some configurations bear the claim
                out, the rest find no difference: neither borne out nor contradicted); "not tested"
                without any comparison. What is not for the claim is against it or within the noise,
                and both count as not for in the share (a claim that predicts a difference is not
                borne out by comparisons that find none): 0-3-0 and 0-0-3 are both "not
                supported", 2-2-1 is "mixed" and 2-0-1 "inconclusive". For and against are treated
                alike: swapping them swaps "supported" and "not supported" and keeps "mixed";
                the within-noise comparisons are the one asymmetry (they count as not for: 0-1-2 is
                "not supported", 1-0-2 "inconclusive"). That reading is a choice: robustness judges
                every verdict with them on neither side too (noise_reading NEITHER: "not supported"
                then needs 80 % against, the mirror of "supported"; 0-1-2 and 0-0-3 are inconclusive). Each verdict is printed with its counts (for,
                against, within noise, not judged). Claims with rules of their own, stated in their
                modules: (e) is about detection alone (force 0: nothing pushes, so stability,
                helping and tunnelling do not apply); (c) counts a restriction that is not stable
                where the penalty is evidence as improper (for the claim); (b) counts a run that
                tunnelled and fails its criteria against (tunnelling can only make it pass).
  robustness    (claims, harness_results/robustness.py) every verdict is judged again under every
                combination of the rule's free choices (VARIANTS: the rho limits halved and doubled,
                the marginal band counted stable, the relative tie 0 or 5 % instead of 10 %, the
                reference's floor or its Richardson estimate or twice the floor or the mesh floor beside
                it, up to 10 nodes
                tunnelled over the window instead of none, two decisive comparisons sufficing instead
                of three, a run helping at 80 % of the no-force run's figures instead of 90 %, rho over
                the whole time before the window (the old normalisation), the final window halved and
                doubled, every method against the two-sided reference instead of the reference of its
                kind: the last two from accuracy_time.csv's runs judged again, accuracy_variants.csv); a
                verdict is stated
                as it is only when every variant agrees, else "fragile (...)": the variants under
                which it flips are named (results/robustness.csv).
"""

import math
import os
import re

from . import reader
from . import reference_kind
from .reference_kind import OF_ITS_KIND, KindFloor, as_two_sided, same_kind_base  # noqa: F401 (re-exported)
from .loading_period import forcing_end, forcing_end_of, loading_rho, renormalised_rho, scene_window  # noqa: F401

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
# The claims' relative tie, decisive comparisons a verdict needs, and the share for that separates
# the verdicts (verdict above).
TIE = 0.10
MIN_DECISIVE = 3
MIXED_SHARE = 0.2
# How the within-noise comparisons count in a verdict (Variant.noise_reading).
NOT_FOR, NEITHER = "not for", "neither"


class Variant:
    """One choice of the rule's free parameters (robustness above): rho_scale multiplies the
    stability limits (INJECTION_LIMIT with its MARGIN band), marginal says whether the marginal band
    counts as stable, tie is the relative tie of the noise, floor which floor of the reference the
    noise takes ("floor": reader.reference_floor, "richardson": the last level's Richardson estimate,
    "double": twice the floor, "mesh": the larger of the floor and the scene's mesh floor, its
    reference on a mesh refined once against the reference on its own mesh)."""

    def __init__(self, rho_scale=1.0, marginal="unstable", tie=TIE, floor="floor", tunnel_limit=0,
                 min_decisive=MIN_DECISIVE, helps=USEFUL, rho_norm="recorded", window=1.0, reference=OF_ITS_KIND,
                 noise_reading=NOT_FOR):
        self.rho_scale, self.marginal, self.tie, self.floor = rho_scale, marginal, tie, floor
        self.tunnel_limit = tunnel_limit  # nodes a run may tunnel over the window and still be evidence
        self.min_decisive = min_decisive  # decisive comparisons a verdict needs (MIN_DECISIVE)
        self.helps = helps                # a run helps at this share of the no-force run's figures (USEFUL)
        # rho as each run recorded it ("recorded": over the loading period, every committed study file and
        # the report's runs), over the loading period for all that allow it ("loading") or over the whole
        # time before the window ("before": the old normalisation; reader.rho_over, renormalised_rho)
        self.rho_norm = rho_norm
        # the final window's length over the scene's time.window (accuracy_variants.csv: the runs judged
        # again over half and twice it) and the reference each method is judged against: OF_ITS_KIND
        # (one-sided methods against the one-sided reference, both ways against the two-sided) or
        # "both ways" (every method against the two-sided reference)
        self.window, self.reference = window, reference
        # how the within-noise comparisons count in the verdict (claim_verdict): as not for (NOT_FOR, the
        # rule as written: a predicted difference that is not found does not bear the claim out) or on
        # neither side (NEITHER: not supported then needs the comparisons against, mirror of supported)
        self.noise_reading = noise_reading

    def name(self):
        """"rho x0.5, marginal stable, tie 5 %, floor richardson": the choices that differ from the default."""
        parts = []
        if self.rho_scale != 1.0:
            parts.append("rho limits x%g" % self.rho_scale)
        if self.marginal != "unstable":
            parts.append("marginal counted %s" % self.marginal)
        if self.tie != TIE:
            parts.append("tie %g %%" % (100 * self.tie))
        if self.floor != "floor":
            parts.append({"richardson": "floor = Richardson estimate", "double": "floor x2",
                          "mesh": "mesh floor in the noise"}.get(self.floor, self.floor))
        if self.tunnel_limit:
            parts.append("up to %d tunnelled nodes" % self.tunnel_limit)
        if self.min_decisive != MIN_DECISIVE:
            parts.append("%d decisive comparisons suffice" % self.min_decisive)
        if self.helps != USEFUL:
            parts.append("helps at %g %% of no force" % (100 * self.helps))
        if self.rho_norm == "loading":
            parts.append("rho over the loading period")
        elif self.rho_norm == "before":
            parts.append("rho over the time before the window")
        if self.window != 1.0:
            parts.append("window x%g" % self.window)
        if self.reference != OF_ITS_KIND:
            parts.append("every method against the %s reference" % self.reference)
        if self.noise_reading != NOT_FOR:
            parts.append("within-noise comparisons on neither side")
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
    x = reader.stability_inputs(s, None if CURRENT.rho_norm == "recorded" else CURRENT.rho_norm)
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
    limit = INJECTION_LIMIT * CURRENT.rho_scale
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
    if CURRENT.rho_norm in ("loading", "before"):
        rho = renormalised_rho(row, rho, CURRENT.rho_norm)
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
    folder `root` (under the current window and reference choices: variant_rows), what "helps" is
    judged against ({} without the file)."""
    rows = reader.read_csv(os.path.join(root, "accuracy_time.csv"), text=reader.STUDY_TEXT, missing=[])
    rows = variant_rows(root, rows)
    return {r["scene"]: as_two_sided(r) for r in rows if r.get("config") == NO_FORCE}


def variant_rows(root, rows):
    """accuracy_time.csv's rows under the current choice of window and reference (CURRENT.window,
    CURRENT.reference): reference_kind.variant_rows."""
    return reference_kind.variant_rows(root, rows, CURRENT.window, CURRENT.reference)


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
# The claims on equal footing: comparisons beyond the noise, four verdicts
WITHIN_NOISE, NOT_STABLE, MISSING = "within noise", "not stable", "missing"
TUNNELS, NO_HELP = "tunnels", "no better than no force"
NOT_JUDGED = (NOT_STABLE, MISSING, TUNNELS, NO_HELP)
SUPPORTED, NOT_SUPPORTED, NOT_TESTED, MIXED = "supported", "not supported", "not tested", "mixed"
VERDICTS = (SUPPORTED, NOT_SUPPORTED, MIXED, INCONCLUSIVE, NOT_TESTED)


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


def decide_stable_wins(a, b, key="pos_err_max_mm", floor=0.0, tie=None):
    """decide, but where one row is evidence and the other is not (not stable, tunnels, or no better
    than no force), the evidence wins ("a" or "b"): a setting that holds against one that does not is
    a finding whatever the errors (the swap's rule). Neither evidence: as decide (why not judged)."""
    ga, gb = evidence_gap(a), evidence_gap(b)
    if ga is None and gb is not None:
        return "a"
    if gb is None and ga is not None:
        return "b"
    return decide(a, b, key, floor, tie)


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


def claim_verdict(outcomes, expected="a", minimum=None):
    """A claim's verdict over its comparisons' outcomes (verdict above); `expected` the outcome the
    claim predicts; `minimum` the decisive comparisons it needs (MIN_DECISIVE unless the claim states
    and argues its own). Outcomes other than `expected`, WITHIN_NOISE and the not-judged ones go
    against it."""
    outcomes = list(outcomes)
    if not outcomes:
        return NOT_TESTED
    t = tally(outcomes, expected)
    decisive = t["for"] + t["against"] + t["noise"]
    if decisive < (CURRENT.min_decisive if minimum is None else minimum):
        return INCONCLUSIVE
    if t["for"] > MIXED_SHARE * decisive and t["against"] > MIXED_SHARE * decisive:
        return MIXED
    if t["for"] >= (1.0 - MIXED_SHARE) * decisive:
        return SUPPORTED
    if CURRENT.noise_reading == NEITHER:  # the mirror of supported: the comparisons against decide it
        return NOT_SUPPORTED if t["against"] >= (1.0 - MIXED_SHARE) * decisive else INCONCLUSIVE
    if t["for"] <= MIXED_SHARE * decisive:
        return NOT_SUPPORTED
    return INCONCLUSIVE  # for in between, nothing against beyond the share: the rest within the noise


def tally(outcomes, expected="a"):
    """{"for", "against", "noise", "not judged"}: the counts a verdict is printed with."""
    outcomes = list(outcomes)
    t = {"for": 0, "against": 0, "noise": 0, "not judged": 0}
    for o in outcomes:
        if o == expected:
            t["for"] += 1
        elif o == WITHIN_NOISE:
            t["noise"] += 1
        elif o in NOT_JUDGED:
            t["not judged"] += 1
        else:
            t["against"] += 1
    return t


def tally_text(t):
    """"2 for, 1 against, 3 within the noise, 4 not judged (a run not evidence or a figure missing)"."""
    return "%d for, %d against, %d within the noise, %d not judged (a run not evidence or a figure missing)" % (
        t["for"], t["against"], t["noise"], t["not judged"])
