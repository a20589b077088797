"""rewindow.py: a finished run judged again over another window, from its steps.csv, must give the
harness's own figures over the scene's window (judge_stability, Series::over), so that its figures
over half and twice the window are the same rule over another span."""

import copy
import math
import os

import pytest

from harness_results import reader, rewindow

ROOT = os.path.join(os.path.dirname(__file__), "..", "..", "results", "runs")
RUNS = sorted(d for d in os.listdir(ROOT) if reader.stored(os.path.join(ROOT, d, "steps.csv"))) \
    if os.path.isdir(ROOT) else []


def close(a, b):
    """steps.csv prints 9 significant digits: window amplitudes of micrometre figures and the
    difference of two cumulative works keep about 5 of them, and a window amplitude of a length is
    exact to 1e-10 m (two printed values of about 1e-2 m)."""
    if isinstance(a, bool) or not isinstance(a, (int, float)):
        return a == b
    return a == b or abs(a - b) <= 1e-5 * max(abs(a), abs(b)) + 1e-10 or (math.isnan(a) and math.isnan(b))


def differences(a, b, path=""):
    if isinstance(a, dict):
        return sum((differences(v, b.get(k), path + "/" + k) for k, v in a.items() if isinstance(b, dict) and k in b), [])
    return [] if close(a, b) else [(path, a, b)]


@pytest.mark.parametrize("run", RUNS)
def test_factor_one_reproduces_the_harness(run):
    folder = os.path.join(ROOT, run)
    s = reader.load_summary(folder)
    r = rewindow.rewindow(folder, s, 1, recompute=True)
    assert r["stability_verdict"] == s["stability_verdict"]
    bad = differences(s["window"], r["window"], "window")
    ew = reader.reference_window(s)
    bad += differences(ew, reader.reference_window(r), "error window")
    assert not bad, bad[:5]


def test_another_window_is_another_span():
    if not RUNS:
        pytest.skip("no committed runs")
    folder = os.path.join(ROOT, RUNS[0])
    s = reader.load_summary(folder)
    w = s["window"]
    n = rewindow.scene_window(s)
    for f in (0.5, 2.0):
        r = rewindow.rewindow(folder, s, f)
        rw = r["window"]
        assert rw["to_step"] == w["to_step"]
        expect = max(w["to_step"] - round(f * n) + 1, int(w["forcing_ends_step"]) + 1, 1)
        assert rw["from_step"] == expect
        assert reader.reference_window(r)["pos_err_max"]["measured_steps"] >= 1
    # half the window measures at most as many steps, twice at least as many
    half = reader.reference_window(rewindow.rewindow(folder, s, 0.5))["pos_err_max"]["measured_steps"]
    full = reader.reference_window(s)["pos_err_max"]["measured_steps"]
    assert half <= full


def test_a_changed_rule_is_found():
    """The factor-one check fails when the rule differs: rho over the time before the window (the
    rule before the loading period) is not what the harness records."""
    if not RUNS:
        pytest.skip("no committed runs")
    run = next((r for r in RUNS if reader.load_summary(os.path.join(ROOT, r))["window"].get("forcing_ends_step")), None)
    if run is None:
        pytest.skip("no forced run")
    folder = os.path.join(ROOT, run)
    s = reader.load_summary(folder)
    wrong = copy.deepcopy(s)
    wrong["window"]["forcing_ends_step"] = 0  # as if nothing forced the scene: t_in = the window
    r = rewindow.rewindow(folder, wrong, 1, recompute=True)
    assert not close(r["window"]["contact_power_ratio"], s["window"]["contact_power_ratio"])


def test_also_reference_swaps_the_two():
    s = {"compare": {"dir": "refs/a"}, "pairs": [{"error_vs_reference": {
        "pos_err_max": 1.0, "pos_err_rms": 0.5, "gap_max": 0.1, "gap_mean": 0.05, "depth_max": 0.2,
        "window": {"pos_err_max": {"mean": 1.0}, "depth_max": {"max": 0.2}}},
        "error_vs_reference_also": {"dir": "refs/b", "pos_err_max": 3.0, "pos_err_rms": 1.5, "gap_max": 0.3,
                                    "gap_mean": 0.1, "window": {"pos_err_max": {"mean": 3.0}}}}]}
    t = rewindow.also_reference(s)
    e = t["pairs"][0]["error_vs_reference"]
    assert e["pos_err_max"] == 3.0 and e["window"]["pos_err_max"]["mean"] == 3.0
    assert e["depth_max"] == 0.2 and e["window"]["depth_max"]["max"] == 0.2  # not a figure of the reference
    assert t["compare"]["dir"] == "refs/b"
    back = rewindow.also_reference(t)
    assert back["pairs"][0]["error_vs_reference"]["pos_err_max"] == 1.0
    assert back["compare"]["dir"] == "refs/a"
    assert rewindow.also_reference({"pairs": [{"error_vs_reference": {}}]}) is None
