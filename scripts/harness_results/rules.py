"""The written rules of the studies and the claims, stated once (scripts/study.py prints this text
in its --help), each implemented below and tested in tests/scripts/.

Definitions:
  window        the final time.window steps of a run (default 1000), after every driver, load and
                pressure ramp has finished (core/run/window.hpp); every run is measured by CGAL every
                STUDY_EVERY = 10 steps (one sampling rule for runs, sweeps and studies).
  error         against the scene's reference (core/run/compare.hpp), over the window: pos_err_max (largest
                distance of a surface vertex from where the reference has it) as its window mean, with
                its window maximum and chatter amplitude (max - min); gap_max (largest gap where the
                reference has contact) window mean; depth_max (deepest node inside the other body)
                window maximum, and its peak over the whole run; tunnelled nodes (through the other
                body) window maximum.
  stable        by the run's contact power over the window against the power the scene put in
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
  rule          (the defaults) among the stable settings whose pos_err_max or depth_max is at most 90 %
                of the run without contact force (a default must do something), the smallest pos_err_max; among
                those within 10 % of it, the smallest gap_max; among those, the fastest. None such:
                no default (and no CI threshold) for that scenario, said in ablation.md.
  front         the Pareto front of error (pos_err_max) against time (t_contact) over the stable settings.
  comparison    (claims) two runs by a figure, smaller better: one is better when its figure is smaller
                by over a stated share of the other's, a tie otherwise; "inconclusive" when either run
                is not stable. A verdict over comparisons: "inconclusive" when any of them is,
                "supported" when all come out as the claim says, "partly supported" when some do, "not
                supported" when none does ("not tested" without any).
"""

import math

from . import reader

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


# ---------------------------------------------------------------------------------------------
# Stability of one run
def classify(s):
    """(class, reasons) of one run's summary by the written rule (stable above): "stable",
    "marginal", "unstable" or "failed"."""
    x = reader.stability_inputs(s)
    rho, verdict = x["rho"], x["verdict"]
    if x["status"] != "ok":
        return FAILED, ["not finite" if x["finite"] is False else str(x["status"])]
    reasons = []
    if x["guard_violations"] > 0:
        reasons.append("dt above the limit")
    if verdict == "grows":
        reasons.append("kinetic energy grows over the window (x%.3g)" % x["growth"])
    if x["kicked"]:
        reasons.append("contact kicked the bodies (net work %.3g J still held as motion)" % x["net_contact_work"])
    if not math.isnan(rho) and rho > INJECTION_LIMIT * MARGIN:
        reasons.append("contact power %.3g of the power put in" % rho)
    if abs(x["balance_error"]) > BALANCE:
        reasons.append("energy audit open")
    if reasons:
        return UNSTABLE, reasons
    if verdict != "settled" and not math.isnan(rho) and rho > INJECTION_LIMIT / MARGIN:
        return MARGINAL, ["contact power %.3g of the power put in (within a factor %g of %g)" % (rho, MARGIN, INJECTION_LIMIT)]
    return STABLE, []


def stability_fields(s):
    """The stability columns of a study's row: stable (yes/no), stability (the class), why_unstable."""
    cls, reasons = classify(s)
    return {"stable": "yes" if cls == STABLE else "no", "stability": cls, "why_unstable": "; ".join(reasons)}


def is_stable(row):
    """A study's row (CSV or figures) that the rule called stable."""
    return row.get("stable") == "yes"


# ---------------------------------------------------------------------------------------------
# The defaults and the front
def useful(r, base):
    """At least 10 % closer to the reference than the run without contact force, in position or in depth."""
    return (r["pos_err_max_mm"] <= USEFUL * base["pos_err_max_mm"]
            or r["depth_max_mm"] <= USEFUL * base["depth_max_mm"])


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


def pareto(rows, x="t_contact_us", y="pos_err_max_mm"):
    """The stable rows that no other stable row beats on both x and y (no worse on both, better on one)."""
    ok = [r for r in rows if r["stable"] == "yes" and not math.isnan(r[x]) and not math.isnan(r[y])]
    return [r for r in ok if not any(o is not r and o[x] <= r[x] and o[y] <= r[y] and (o[x] < r[x] or o[y] < r[y])
                                     for o in ok)]


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
# The claims' comparisons and verdicts
def compare(a, b, key="pos_err_max_mm", tie=0.10):
    """Two runs (rows) by `key`, smaller better: "a" or "b" when its figure is smaller than the other's
    by over `tie` (a share), "tie" otherwise; INCONCLUSIVE when either run is not stable or either
    figure is missing (comparison above)."""
    if not (is_stable(a) and is_stable(b)):
        return INCONCLUSIVE
    x, y = a.get(key), b.get(key)
    if not (reader.present(x) and reader.present(y)):
        return INCONCLUSIVE
    if x < (1 - tie) * y:
        return "a"
    if y < (1 - tie) * x:
        return "b"
    return "tie"


def verdict(outcomes, expected="a"):
    """A claim's verdict over the outcomes of its comparisons (compare()), `expected` the outcome
    the claim predicts (comparison above)."""
    outcomes = list(outcomes)
    if not outcomes:
        return "not tested"
    if INCONCLUSIVE in outcomes:
        return INCONCLUSIVE
    hits = sum(1 for o in outcomes if o == expected)
    return share_verdict(hits, len(outcomes))


def share_verdict(hits, total):
    """"supported" when the claim holds in all `total` cases, "partly supported" in some, "not supported" in none."""
    if hits == total:
        return "supported"
    if hits > 0:
        return "partly supported"
    return "not supported"


def better_of(a, b, key="pos_err_max_mm", tie=0.10):
    """'a', 'b' or None: stable where the other is not; else the smaller key by over `tie`; both
    unstable: None. (Claim (a) without its confound.)"""
    if (a["stable"] == "yes") != (b["stable"] == "yes"):
        return "a" if a["stable"] == "yes" else "b"
    if a["stable"] != "yes":
        return None
    if a[key] < (1 - tie) * b[key]:
        return "a"
    if b[key] < (1 - tie) * a[key]:
        return "b"
    return None


def plane_verdict(rows, wins, untested):
    """Claim (a)'s verdict over the implant rows (row[5] the comparison's result)."""
    if not rows:
        return untested
    if wins == len(rows):
        return "supported"
    if wins > 0:
        return "partly supported"
    if all(r[5] == "equal" for r in rows):
        return "inconclusive (no difference)"
    return "not supported"


def dominance(a, b, keys):
    """Of two records compared on `keys` (smaller better): "b better" when b is no worse on all and
    better on one, "a better" the other way round, "equal" when equal on all, "mixed" otherwise."""
    if all(b[k] <= a[k] for k in keys) and any(b[k] < a[k] for k in keys):
        return "b better"
    if all(a[k] <= b[k] for k in keys) and any(a[k] < b[k] for k in keys):
        return "a better"
    if all(a[k] <= b[k] for k in keys) and all(b[k] <= a[k] for k in keys):
        return "equal"
    return "mixed"
