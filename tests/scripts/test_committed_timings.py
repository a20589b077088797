"""study.py accuracy --classes-only (studies/common.py committed_timings): the error runs made again,
each row's timings kept from its committed twin only where its error reproduces the twin's."""
import argparse
import math

from harness_results import writers
from harness_results.studies.common import committed_timings

KEYS = ("scene", "config", "eliminator")


def row(config, err, t=None, tunnelled=0, machine=None):
    r = {"scene": "s", "config": config, "eliminator": "line", "pos_err_max_mm": err, "tunnelled": tunnelled}
    if t is not None:
        r.update(t_step_us=t, t_contact_us=t / 10, t_contact_range="1-2", repeats=5, machine=machine)
    return r


def test_timings_kept_where_the_error_reproduces(tmp_path):
    committed = [row("a", 1.25, t=100.0, machine="old"), row("b", 2.0, t=200.0, machine="old"),
                 row("c", 3.0, t=300.0, tunnelled=2, machine="old")]
    writers.write_csv(str(tmp_path / "x.csv"), committed, list(committed[0].keys()))
    a = argparse.Namespace(results=str(tmp_path), classes_only=True)
    new = [row("a", 1.25, t=7.0, machine="new"), row("b", 2.0001, t=7.0, machine="new"),
           row("c", 3.0, t=7.0, tunnelled=1, machine="new"), row("d", 4.0, t=7.0, machine="new")]
    out = {r["config"]: r for r in committed_timings(a, "x.csv", new, KEYS)}
    assert out["a"]["timings"] == "committed" and out["a"]["t_step_us"] == 100.0 and out["a"]["machine"] == "old"
    assert out["a"]["repeats"] == 5 and out["a"]["t_contact_range"] == "1-2"
    # an error that moved (by 1e-4 mm) or a tunnelling count that changed: other runs, their timings not kept
    for k in ("b", "c"):
        assert out[k]["timings"].startswith("error") and out[k]["t_step_us"] == 7.0 and out[k]["machine"] == "new"
    assert out["d"]["timings"].startswith("no committed twin") and out["d"]["t_step_us"] == 7.0


def test_without_the_flag_nothing_changes(tmp_path):
    a = argparse.Namespace(results=str(tmp_path), classes_only=False)
    rows = [row("a", 1.0, t=7.0)]
    assert committed_timings(a, "missing.csv", rows, KEYS) == rows and "timings" not in rows[0]


def test_nan_errors_reproduce_each_other(tmp_path):
    committed = [row("a", float("nan"), t=100.0)]
    writers.write_csv(str(tmp_path / "x.csv"), committed, list(committed[0].keys()))
    a = argparse.Namespace(results=str(tmp_path), classes_only=True)
    out = committed_timings(a, "x.csv", [row("a", float("nan"), t=7.0)], KEYS)
    assert out[0]["timings"] == "committed" and out[0]["t_step_us"] == 100.0 and math.isnan(out[0]["pos_err_max_mm"])
