"""The claims' comparisons and verdicts (scripts/harness_results/rules.py), on small hand-made
tables: a comparison that rests on a run that is not stable, and so the verdict, is "inconclusive"."""

import os

import pytest

from harness_results import rules
from harness_results.claims import a_orient, e_region, swap
from harness_results.claims.common import Context, Verdict

TABLE = """scene,config,eliminator,stable,stability,pos_err_max_mm,t_contact_us
implant_expansion,voxel 8 mm,line,yes,stable,2.0,10
implant_expansion,voxel 8 mm,plane,yes,stable,1.0,12
cylinder_press,voxel 8 mm,line,yes,stable,2.0,10
cylinder_press,voxel 8 mm,plane,yes,stable,1.9,12
sphere_collision,voxel 8 mm,line,no,marginal,2.0,10
sphere_collision,voxel 8 mm,plane,yes,stable,1.0,12
"""


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return str(tmp_path)


def plane_beats_line(ctx, scenes):
    """A claim as a new claim module would test it: per scene, the plane against the line
    (rules.compare, 10 % ties), the verdict over them (rules.verdict): the plane predicted better."""
    rows = ctx.csv("table.csv", ["pos_err_max_mm"])
    outcomes = []
    for scene in scenes:
        plane, line = [next(r for r in rows if r["scene"] == scene and r["eliminator"] == e) for e in ("plane", "line")]
        outcomes.append(rules.compare(plane, line, "pos_err_max_mm", tie=0.10))
    v = rules.verdict(outcomes, expected="a")
    return Verdict("plane_beats_line", v, ["**Verdict: %s**" % v], [("PlaneBeatsLineVerdict", v)], data=outcomes)


def test_a_verdict_on_a_run_that_is_not_stable_is_inconclusive(tmp_path):
    ctx = Context(write(tmp_path, "table.csv", TABLE))
    # implant: plane 50 % better; cylinder: 5 %, a tie; sphere: the line is marginal (not stable).
    v = plane_beats_line(ctx, ["implant_expansion", "cylinder_press", "sphere_collision"])
    assert v.data == ["a", "tie", "inconclusive"]
    assert v.verdict == "inconclusive"
    # The same claim on the settings whose runs are stable has a verdict.
    assert plane_beats_line(ctx, ["implant_expansion"]).verdict == "supported"
    assert plane_beats_line(ctx, ["implant_expansion", "cylinder_press"]).verdict == "partly supported"
    assert plane_beats_line(ctx, ["cylinder_press"]).verdict == "not supported"


@pytest.mark.parametrize("a, b, expected", [
    (dict(stable="yes", e=1.0), dict(stable="yes", e=2.0), "a"),
    (dict(stable="yes", e=2.0), dict(stable="yes", e=1.0), "b"),
    (dict(stable="yes", e=1.0), dict(stable="yes", e=1.05), "tie"),
    (dict(stable="yes", e=0.9), dict(stable="yes", e=1.0), "tie"),           # exactly 10 % smaller: a tie
    (dict(stable="yes", e=0.89), dict(stable="yes", e=1.0), "a"),
    (dict(stable="no", e=0.1), dict(stable="yes", e=1.0), "inconclusive"),   # the better figure, not stable
    (dict(stable="yes", e=1.0), dict(stable="no", e=9.0), "inconclusive"),
    (dict(stable="no", e=1.0), dict(stable="no", e=9.0), "inconclusive"),
    (dict(stable="yes", e=float("nan")), dict(stable="yes", e=1.0), "inconclusive"),
    (dict(stable="yes"), dict(stable="yes", e=1.0), "inconclusive"),          # figure missing
])
def test_compare(a, b, expected):
    assert rules.compare(a, b, "e", tie=0.10) == expected


@pytest.mark.parametrize("outcomes, expected", [
    ([], "not tested"),
    (["a", "a"], "supported"),
    (["a", "tie"], "partly supported"),
    (["a", "b"], "partly supported"),
    (["tie", "b"], "not supported"),
    (["a", "a", "inconclusive"], "inconclusive"),
    (["inconclusive"], "inconclusive"),
])
def test_verdict(outcomes, expected):
    assert rules.verdict(outcomes, expected="a") == expected


def test_verdict_of_the_other_side():
    assert rules.verdict(["b", "b"], expected="b") == "supported"
    assert rules.verdict(["a", "a"], expected="b") == "not supported"


# ---------------------------------------------------------------------------------------------
# The helpers today's claims use, unchanged
def test_better_of():
    s, u = "yes", "no"
    assert rules.better_of({"stable": s, "e": 5.0}, {"stable": u, "e": 1.0}, "e") == "a"   # stable wins
    assert rules.better_of({"stable": u, "e": 1.0}, {"stable": s, "e": 5.0}, "e") == "b"
    assert rules.better_of({"stable": u, "e": 1.0}, {"stable": u, "e": 5.0}, "e") is None  # both unstable
    assert rules.better_of({"stable": s, "e": 0.89}, {"stable": s, "e": 1.0}, "e") == "a"
    assert rules.better_of({"stable": s, "e": 0.95}, {"stable": s, "e": 1.0}, "e") is None


def test_dominance():
    keys = ["x", "y"]
    assert rules.dominance({"x": 2, "y": 2}, {"x": 1, "y": 2}, keys) == "b better"
    assert rules.dominance({"x": 1, "y": 2}, {"x": 2, "y": 2}, keys) == "a better"
    assert rules.dominance({"x": 1, "y": 2}, {"x": 1, "y": 2}, keys) == "equal"
    assert rules.dominance({"x": 1, "y": 3}, {"x": 2, "y": 2}, keys) == "mixed"


def test_plane_verdict_and_share_verdict():
    rows = [(0, 0, 0, 0, 0, "plane better"), (0, 0, 0, 0, 0, "line better")]
    assert rules.plane_verdict([], 0, "untested") == "untested"
    assert rules.plane_verdict(rows[:1], 1, "") == "supported"
    assert rules.plane_verdict(rows, 1, "") == "partly supported"
    assert rules.plane_verdict(rows[1:], 0, "") == "not supported"
    assert rules.plane_verdict([(0, 0, 0, 0, 0, "equal")] * 2, 0, "") == "inconclusive (no difference)"
    assert [rules.share_verdict(h, 3) for h in (3, 1, 0)] == ["supported", "partly supported", "not supported"]


# ---------------------------------------------------------------------------------------------
# Claims on hand-made study tables (what claims.py writes comes from these records)
ORIENT = "scene,eliminator,orient,force,voxel_mm,stable,pos_err_max_mm\n" + "".join(
    "implant_expansion,%s,%s,%s,8,%s,%s\n" % r for r in [
        # F=0.03: plane better either way
        ("line", "guest", "F=0.03", "yes", 2.0), ("plane", "guest", "F=0.03", "yes", 1.0),
        ("line", "outward", "F=0.03", "yes", 2.0), ("plane", "outward", "F=0.03", "yes", 1.0),
        # auto: every run unstable: not judged
        ("line", "guest", "auto", "no", 2.0), ("plane", "guest", "auto", "no", 1.0),
        ("line", "outward", "auto", "no", 2.0), ("plane", "outward", "auto", "no", 1.0)])


def test_claim_a_without_its_confound_does_not_judge_unstable_pairs(tmp_path):
    v = a_orient.judge(Context(write(tmp_path, "orient.csv", ORIENT)))
    macros = dict(v.macros)
    assert v.verdict == "supported"
    assert (macros["ClaimAOGuestWins"], macros["ClaimAOGuestJudged"]) == ("1", "1")
    assert "both unstable" in "\n".join(v.md)


REGION = "scene,region,margin,stable,pos_err_max_mm,recall,t_contact_us\n" + "".join(
    "cylinder_press,%s,%d,yes,1.0,%s,10\n" % r for r in [
        ("half", 0, 0.5), ("full", 0, 0.95), ("overlap", 0, 0.6),
        ("half", 1, 0.5), ("full", 1, 0.80), ("overlap", 1, 0.6)])


def test_claim_e(tmp_path):
    v = e_region.judge(Context(write(tmp_path, "region.csv", REGION)))
    assert v.verdict == "partly supported"  # full best in both margins, at least 90 % in one
    assert dict(v.macros)["ClaimEFullBest"] == "2" and dict(v.macros)["ClaimEAll"] == "1"


def test_claims_without_their_table(tmp_path):
    ctx = Context(str(tmp_path))
    assert swap.judge(ctx).md == [] and a_orient.judge(ctx).macros == []
    assert not os.listdir(str(tmp_path))
