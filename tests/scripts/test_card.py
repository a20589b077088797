"""The verdict card's sentence (harness_results/card.py judge): every method within the noise of the
closest is named, good or not, and the fastest of the good ones."""

from harness_results import card

BASE = {"pos_err_max_mm": 10.0, "depth_max_mm": 5.0}


def row(method, err, t=10.0, stable="yes", tunnelled=0):
    return {"method": method, "pos_err_max_mm": err, "pos_err_amp_mm": 0.0, "depth_max_mm": 0.1, "stable": stable,
            "stability": "stable" if stable == "yes" else "unstable", "why_unstable": "", "tunnelled_total": tunnelled,
            "t_mean_us": t, "t_p99_us": 2 * t}


def test_ties_within_the_noise_are_named_with_the_fastest():
    s = card.judge([row("a", 1.00, t=30.0), row("b", 1.05, t=20.0), row("c", 2.0, t=5.0)], BASE)
    assert s.startswith("a, b are the closest") and "the fastest of them is b" in s
    s = card.judge([row("a", 1.00), row("b", 1.5)], BASE)
    assert s.startswith("a is the closest")
    # the reference's floor widens the tie
    assert card.judge([row("a", 1.00), row("b", 1.5)], BASE, floor_mm=0.6).startswith("a, b are the closest")


def test_no_good_method_names_every_closest_run():
    s = card.judge([row("a", 0.5, tunnelled=1), row("b", 0.5, tunnelled=1), row("c", 3.0, stable="no")], BASE)
    assert s.startswith("No method is stable") and "a, stable but tunnels; b, stable but tunnels" in s
    s = card.judge([row("a", 0.5, tunnelled=1), row("c", 3.0, stable="no")], BASE)
    assert "the closest run (a, 0.5 mm) is stable but tunnels" in s
