"""The report's counts (harness_results/counts.py): the best setting of a family is the least error,
the fastest among errors within the claims' noise of it; the committed counts.tex is what counts.py writes from the committed
results."""

import os

from harness_results import counts, rules

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def test_best_is_least_error_then_fastest():
    rows = [{"pos_err_max_mm": "0.5", "t_contact_us": "146", "config": "hash"},
            {"pos_err_max_mm": "0.5", "t_contact_us": "41.1", "config": "cgal"},
            {"pos_err_max_mm": "0.7", "t_contact_us": "1", "config": "voxel"}]
    assert counts.best_of(rows)["config"] == "cgal"
    assert counts.best_of(list(reversed(rows)))["config"] == "cgal"
    rows.append({"pos_err_max_mm": "0.4", "t_contact_us": "", "config": "untimed"})
    assert counts.best_of(rows)["config"] == "untimed"  # error first; a missing time is no reason to drop it
    assert counts.best_of([]) is None
    # within the noise of the least error (the relative tie, the chatters, the references' floors): the fastest
    near = [{"pos_err_max_mm": "0.0879", "t_contact_us": "1851", "config": "16 mm both", "reference": "both ways"},
            {"pos_err_max_mm": "0.102", "t_contact_us": "758", "config": "8 mm one", "reference": "one-sided"}]
    assert counts.best_of(near)["config"] == "16 mm both"                        # 0.014 apart: beyond 10 %
    floors = rules.KindFloor({"both ways": 0.013, "one-sided": 0.264})
    assert counts.best_of(near, floors)["config"] == "8 mm one"                  # within the one-way floor
    assert counts.best_of(near, rules.KindFloor({"both ways": 0.013, "one-sided": 0.001}))["config"] == "16 mm both"


def test_committed_counts_are_written_from_the_results():
    committed = os.path.join(ROOT, "results", "tables", "counts.tex")
    with open(committed) as f:
        lines = [l for l in f.read().splitlines() if l.startswith("\\newcommand")]
    written = ["\\newcommand{\\%s}{%s}" % (n, v) for n, v in counts.collect(os.path.join(ROOT, "results"))]
    assert lines == written


def test_times_for_prose_have_no_exponent():
    assert counts.num3("1483.92") == "1480"
    assert counts.num3("41.091") == "41.1"
    assert counts.num3("0.00123") == "0.00123"
    assert counts.num3("") is None and counts.num3("nan") == "--"
