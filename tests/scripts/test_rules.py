"""The written rules (scripts/harness_results/rules.py) on small hand-made summaries and tables:
stability with its margin, the defaults' choice, the Pareto front."""

import math

import pytest

from harness_results import rules
from harness_results.studies.common import figures

NAN = float("nan")


def summary(status="ok", verdict="steady", guard=0, finite=True, rho=None, growth=1.0):
    """A summary.json holding what the stability columns read (rho and growth: ignored now)."""
    return {"status": status, "finite": finite, "stability_verdict": verdict,
            "window": {"contact_power_ratio": rho, "kinetic_growth": growth},
            "stability": {"guard_violations": guard}}


# ---------------------------------------------------------------------------------------------
# Stability: the run's C++ class decides; a run that did not end ok failed
@pytest.mark.parametrize("verdict, stable", [("settled", "yes"), ("steady", "yes"), ("chatters", "no"),
                                             ("injects", "no"), ("grows", "no"), ("forced", "no"), (None, "no")])
def test_the_class_decides(verdict, stable):
    f = rules.stability_fields(summary(verdict=verdict))
    assert f["stable"] == stable and f["stability_class"] == (verdict or "")
    assert (f["why_unstable"] == "") == (stable == "yes")
    assert rules.is_stable(f) == (stable == "yes")


def test_the_contact_power_no_longer_decides():
    # what the old rule called unstable (rho 0.5, kinetic energy doubled) is stable when the class is steady
    assert rules.stability_fields(summary(verdict="steady", rho=0.5, growth=2.06))["stable"] == "yes"
    # and a chattering run with no contact power at all is not
    assert rules.stability_fields(summary(verdict="chatters", rho=0.0))["stable"] == "no"


def test_a_guard_violation_is_not_stable_whatever_the_class():
    f = rules.stability_fields(summary(verdict="settled", guard=1))
    assert f["stable"] == "no" and "dt above the limit" in f["why_unstable"]


@pytest.mark.parametrize("status, finite, why", [("error", False, "not finite"), ("error", True, "error"),
                                                  ("interrupted", True, "interrupted")])
def test_a_run_that_did_not_end_ok_failed(status, finite, why):
    f = rules.stability_fields(summary(status=status, finite=finite, verdict="settled"))
    assert (f["stable"], f["stability"], f["why_unstable"]) == ("no", "failed", why)
    # the judge reads stability_class first: a run that did not end ok fails there too
    assert f["stability_class"] == "failed"


def test_a_row_of_figures_carries_the_class():
    f = figures(summary(verdict="chatters"))  # a study's row: window figures with the judgement
    assert (f["stable"], f["stability"], f["stability_class"]) == ("no", "chatters", "chatters")
    assert math.isnan(f["pos_err_max_mm"])


def test_a_table_says_which_rule_made_its_rows():
    new, old = {"stability_class": "steady"}, {"stability": "stable"}
    assert rules.stability_source([new, new]).startswith("the run's C++ stability class")
    assert rules.stability_source([old]).startswith("the rule these rows were written with")
    assert "for the 1 rows that record it; for the other 2" in rules.stability_source([new, old, old])


# ---------------------------------------------------------------------------------------------
# The defaults' rule: stable, useful, smallest error, within 10 % the smallest gap, then the fastest
def row(name, pos, gap=1.0, t=10.0, stable="yes", depth=5.0):
    return {"name": name, "pos_err_max_mm": pos, "gap_max_mm": gap, "t_contact_us": t, "stable": stable,
            "depth_max_mm": depth}


def chosen(rows, baseline=None):
    r = rules.choose(rows, baseline)
    return None if r is None else r["name"]


def test_choose_the_smallest_error_among_the_stable():
    rows = [row("unstable best", 0.1, stable="no"), row("a", 2.0), row("b", 1.0), row("nan", NAN)]
    assert chosen(rows) == "b"


def test_within_ten_percent_the_smallest_gap():
    # b is within 10 % of the best error (1.1 <= 1.1 x 1.0) and has the smaller gap: b.
    assert chosen([row("a", 1.0, gap=2.0), row("b", 1.1, gap=1.0)]) == "b"
    # c is not within 10 % (1.11 > 1.1): the best error wins whatever c's gap.
    assert chosen([row("a", 1.0, gap=2.0), row("c", 1.11, gap=0.1)]) == "a"


def test_within_ten_percent_of_the_gap_the_fastest():
    rows = [row("a", 1.0, gap=2.0, t=30.0),   # best error, slow
            row("b", 1.05, gap=2.2, t=20.0),  # gap within 10 % of 2.0: in; faster than a
            row("c", 1.02, gap=2.3, t=1.0),   # gap over 10 % above 2.0: out, however fast
            row("d", 1.5, gap=2.0, t=0.5)]    # error not within 10 %: out, however fast
    assert chosen(rows) == "b"
    assert chosen(rows[:1] + rows[2:]) == "a"


def test_a_default_must_beat_no_force_by_ten_percent():
    base = {"pos_err_max_mm": 10.0, "depth_max_mm": 10.0}
    assert chosen([row("a", 9.5, depth=9.5)], base) is None                      # 95 %: not useful
    assert chosen([row("a", 9.0, depth=9.5)], base) == "a"                       # 90 % in position
    assert chosen([row("a", 10.0, depth=9.0)], base) == "a"                      # 90 % in depth, no worse in position
    assert chosen([row("a", 12.0, depth=9.0)], base) is None                     # shallower, but farther than no force
    assert chosen([row("a", 20.0, depth=0.0)], base) is None                     # held apart: depth 0, error doubled
    assert chosen([row("a", 9.5, depth=9.5), row("b", 10.0, depth=1.0)], base) == "b"
    assert rules.useful(row("a", 9.0, depth=20.0), base) and not rules.useful(row("a", 9.01, depth=9.01), base)


def test_none_qualifies():
    assert chosen([]) is None
    assert chosen([row("a", 1.0, stable="no"), row("b", NAN)]) is None
    assert chosen([row("a", 50.0, depth=50.0)], {"pos_err_max_mm": 10.0, "depth_max_mm": 10.0}) is None


def test_choose_when_no_tied_row_has_a_gap():
    # No gap figure in any tied row: the gap rule cannot split them; the faster one is chosen.
    assert chosen([row("a", 1.0, gap=NAN), row("b", 1.05, gap=NAN)]) in ("a", "b")
    # One tied row with a gap, one without: the one without is not dropped by the other's gap.
    assert chosen([row("a", 1.0, gap=NAN), row("b", 1.05, gap=0.5)]) in ("a", "b")


# ---------------------------------------------------------------------------------------------
# The Pareto front of error against time over the evidence, with ties within the noise
def point(name, t, err, stable="yes", lo=None, hi=None, tunnelled=0, helps="yes", amp=0.0):
    return {"name": name, "t_contact_us": t, "t_contact_min_us": t if lo is None else lo,
            "t_contact_max_us": t if hi is None else hi, "pos_err_max_mm": err, "pos_err_amp_mm": amp,
            "stable": stable, "tunnelled": tunnelled, "helps": helps}


def front(rows, floor=0.0):
    return sorted(r["name"] for r in rules.pareto(rows, floor=floor))


def test_pareto_front():
    rows = [point("fast", 1.0, 5.0), point("mid", 2.0, 3.0), point("dominated", 3.0, 4.0),
            point("accurate", 4.0, 1.0), point("slow and bad", 5.0, 5.0)]
    assert front(rows) == ["accurate", "fast", "mid"]


def test_pareto_ties_and_dominance_on_one_axis():
    # equal on both axes: neither beats the other; equal time and a larger error: beaten
    rows = [point("a", 2.0, 3.0), point("a2", 2.0, 3.0), point("same time, worse", 2.0, 3.5),
            point("same error, slower", 2.5, 3.0)]
    assert front(rows) == ["a", "a2"]


def test_pareto_only_evidence_and_measured():
    rows = [point("unstable", 0.1, 0.1, stable="no"), point("nan", NAN, 0.1), point("nan err", 0.1, NAN),
            point("tunnels", 0.1, 0.1, tunnelled=1), point("no help", 0.1, 0.1, helps="no"), point("a", 1.0, 1.0)]
    assert front(rows) == ["a"]
    # a tunnel allowance lets the tunnelling run in
    assert [r["name"] for r in rules.pareto(rows, rule=rules.TableRules(tunnel_limit=10))] == ["tunnels"]


def test_pareto_errors_within_the_noise_are_equal():
    # 1.05 and 1.00 differ by less than 10 %: the faster one beats the slower, though its error is larger
    rows = [point("fast", 1.0, 1.05), point("slow", 2.0, 1.00)]
    assert front(rows) == ["fast"]
    # strict: both stay
    assert [r["name"] for r in rules.pareto(rows, rule=rules.TableRules(tie=0.0))] == ["fast", "slow"]
    # the reference's floor makes a difference beyond the relative tie equal too
    rows = [point("fast", 1.0, 0.30), point("slow", 2.0, 0.10)]
    assert front(rows) == ["fast", "slow"]
    assert front(rows, floor=0.25) == ["fast"]
    # so do the two runs' chatters
    rows = [point("fast", 1.0, 0.30, amp=0.1), point("slow", 2.0, 0.10, amp=0.15)]
    assert front(rows) == ["fast"]


def test_pareto_times_within_their_ranges_are_equal():
    # medians 1 and 2 but overlapping ranges: equal in time, so the more accurate one beats the other
    rows = [point("fast", 1.0, 3.0, lo=0.5, hi=2.5), point("accurate", 2.0, 1.0, lo=1.5, hi=3.0)]
    assert front(rows) == ["accurate"]
    # equal on both axes within the noise: both stay
    rows = [point("a", 1.0, 1.00, lo=0.5, hi=2.5), point("b", 2.0, 1.05, lo=1.5, hi=3.0)]
    assert front(rows) == ["a", "b"]


def test_useless_words_and_marks():
    base = {"pos_err_max_mm": 10.0, "depth_max_mm": 5.0}
    rows = [{"scene": "s", "config": "m", "pos_err_max_mm": 8.0, "depth_max_mm": 5.0, "tunnelled": 0},
            {"scene": "s", "config": "m", "pos_err_max_mm": 9.5, "depth_max_mm": 5.0, "tunnelled": 0},
            {"scene": "s", "config": "m", "pos_err_max_mm": 9.5, "depth_max_mm": 5.0, "tunnelled": 3},
            {"scene": "s", "config": "m", "pos_err_max_mm": 1.0, "depth_max_mm": 1.0, "tunnelled": 1},
            {"scene": "s", "config": rules.NO_FORCE, "pos_err_max_mm": 10.0, "depth_max_mm": 5.0, "tunnelled": 0},
            {"scene": "other", "config": "m", "pos_err_max_mm": 1.0, "depth_max_mm": 1.0, "tunnelled": 0}]
    rules.mark_useless(rows, {"s": base})
    assert [r["helps"] for r in rows] == ["yes", "no", "no", "yes", "", ""]
    assert [r["useless"] for r in rows] == ["", rules.NO_HELP, rules.TUNNELS + "; " + rules.NO_HELP, rules.TUNNELS,
                                            "baseline", ""]
    assert rules.useless_text(rows[3], rules.TableRules(tunnel_limit=10)) == ""
    # no depth recorded: a row the depth alone could make help is not judged ("", not "no")
    assert rules.helps_word({"pos_err_max_mm": 9.5}, base) == ""
    assert rules.helps_word({"pos_err_max_mm": 10.5}, base) == "no"
    assert rules.helps_word({"pos_err_max_mm": 8.0}, base) == "yes"


def test_median_and_nearest_rank():
    assert rules.median([3.0, NAN, 1.0, 2.0]) == 2.0
    assert rules.median([4.0, 1.0, 2.0, 3.0]) == 2.5
    assert math.isnan(rules.median([NAN]))
    assert rules.nearest_rank([10, 20, 30, 40, 50, 60, 70, 80, 90, 100], 90) == 90
    assert rules.nearest_rank([10, 20, 30], 50) == 20
    assert rules.nearest_rank([], 50) is None


def test_regime_swaps_where_evidence_against_either_reference():
    """study.py regime runs a setting swapped where its scene placement is evidence against the
    reference of its kind or against the two-sided one (its helps judged again there)."""
    from harness_results.studies.regime import evidence_either_kind
    base = {"pos_err_max_mm": 10.0, "depth_max_mm": 5.0, "reference": "one-sided",
            "pos_err_max_one_sided_mm": 10.0, "pos_err_max_both_ways_mm": 12.0}
    row = {"stable": "yes", "stability": "stable", "tunnelled": 0, "pos_err_max_mm": 9.95, "depth_max_mm": 5.0,
           "reference": "one-sided", "pos_err_max_one_sided_mm": 9.95, "pos_err_max_both_ways_mm": 6.0}
    row["helps"] = rules.helps_word(row, base)
    assert row["helps"] == "no" and rules.evidence_gap(row) is not None  # one-sided: 9.95 against 10
    assert evidence_either_kind(row, base)  # both ways: 6.0 against 12.0 helps
    assert not evidence_either_kind(dict(row, pos_err_max_both_ways_mm=11.9), base)
    assert not evidence_either_kind(dict(row, stable="no", stability="unstable", pos_err_max_both_ways_mm=6.0), base)
