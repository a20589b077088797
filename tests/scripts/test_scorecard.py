"""The scorecard's standing (harness_results/scorecard.py): a user's method against the built-in
method with the least error that does not fail, by the interval of the error ratio; a failing run
loses; a card row read as the judge reads a study's row."""

import math

from harness_results import scorecard
from harness_results.judge import measure


def run(label, err, lo=None, hi=None, failed="", t=10.0):
    lo = err if lo is None else lo
    hi = err if hi is None else hi
    return measure.Run({}, label, failed, "steady", "run", err, lo, hi, t, t, t, 1.0)


def test_closer_farther_and_cannot_tell_follow_the_interval():
    builtin = [run("voxel", 5.0, 4.9, 5.1), run("cgal", 1.0, 0.9, 1.1), run("box", 0.1, 0.09, 0.11, failed="3 nodes through")]
    word, eff, t, best = scorecard.standing(run("mine", 0.5, 0.45, 0.55, t=20.0), builtin)
    assert (word, best.label) == ("closer", "cgal") and eff.hi < 1 and t == 2.0  # the failing box is not the best
    assert scorecard.standing(run("mine", 2.0, 1.8, 2.2), builtin)[0] == "farther"
    assert scorecard.standing(run("mine", 1.0, 0.95, 1.05), builtin)[0] == "cannot tell"  # overlapping intervals


def test_a_failing_method_loses_and_no_passing_builtin_is_said():
    builtin = [run("cgal", 1.0)]
    word, eff, t, best = scorecard.standing(run("mine", 0.1, failed="blew up"), builtin)
    assert word == "fails" and eff is None and math.isnan(t) and best.label == "cgal"
    assert scorecard.standing(run("mine", 0.1), [run("cgal", 1.0, failed="unstable")])[0] == "no built-in passes"


def test_a_card_row_is_read_as_the_judge_reads_a_row():
    row = {"method": "m", "verdict": "steady", "status": "ok", "forced": "no", "pos_err_max_mm": 1.0,
           "pos_err_max_max_mm": 1.2, "pos_err_amp_mm": 0.4, "tunnelled_total": 0, "t_mean_us": 50.0}
    assert scorecard.judge_row(row, "s")["stability_class"] == "steady"
    assert scorecard.judge_row(dict(row, forced="yes"), "s")["stability_class"] == "forced"
    assert scorecard.judge_row(dict(row, status="error"), "s")["stability_class"] == "failed"
    # through the judge: the window's range widened by the floor; a node through fails
    scenes = type("S", (), {"floor_mm": lambda self, s, k: 0.1, "spacing_mm": lambda self, s: 1.0,
                            "mesh_floor_mm": lambda self: math.nan, "ensemble_of": lambda self, r: None})()
    spec = scorecard.choices.DEFAULT
    x = measure.measure(scorecard.judge_row(row, "s"), spec, scenes, label="m", time_key="t_mean")
    assert not x.failed and math.isclose(x.err_lo, 0.7) and math.isclose(x.err_hi, 1.3) and x.t == 50.0
    y = measure.measure(scorecard.judge_row(dict(row, tunnelled_total=2), "s"), spec, scenes, label="m", time_key="t_mean")
    assert y.failed == "2 nodes through"
    z = measure.measure(scorecard.judge_row(dict(row, verdict="chatters"), "s"), spec, scenes, label="m", time_key="t_mean")
    assert z.failed.startswith("chatters")


def test_without_a_method_it_says_so_with_exit_2():
    import os
    import subprocess
    import sys
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p = subprocess.run([sys.executable, os.path.join(root, "scripts", "study.py"), "scorecard"], capture_output=True,
                       text=True)
    assert p.returncode == 2 and "--method" in p.stderr and len(p.stderr.strip().splitlines()) == 1
    p = subprocess.run([sys.executable, os.path.join(root, "scripts", "study.py"), "scorecard", "--scene", "x.json",
                        "--method", "m=contacts.0.force=1"], capture_output=True, text=True)
    assert p.returncode == 2 and "--scenes" in p.stderr
