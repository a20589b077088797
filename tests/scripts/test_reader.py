"""The one CSV reader and the summary accessors (scripts/harness_results/reader.py)."""

import math

from harness_results import reader

CSV = """scene,force,stable,why_unstable,pos_err_max_mm,front,note,step
a,F=0.01,yes,,1.5,,,1
b,auto,no,energy audit open,,yes,,2
"""


def test_missing_numbers_are_nan_and_text_stays_text(tmp_path):
    p = tmp_path / "t.csv"
    p.write_text(CSV)
    rows = reader.read_csv(str(p), numbers=["t_step_us"], text=reader.STUDY_TEXT)
    a, b = rows
    assert a["pos_err_max_mm"] == 1.5 and math.isnan(b["pos_err_max_mm"])
    assert (a["why_unstable"], b["why_unstable"]) == ("", "energy audit open")
    assert (a["front"], b["front"]) == ("", "yes")       # named text: "" where empty
    assert a["force"] == "F=0.01" and a["step"] == 1.0
    assert math.isnan(a["note"])                         # not named, nothing in it: a number column
    assert math.isnan(a["t_step_us"])                    # asked for, not in the file
    assert not reader.present(b["pos_err_max_mm"]) and not reader.present("") and reader.present(0.0)


def test_a_column_holding_text_is_text(tmp_path):
    p = tmp_path / "steps.csv"
    p.write_text("step,pair,force\n1,a/b,0.5\n2,a/b,\n")
    cols = reader.columns(reader.read_csv(str(p)))
    assert cols["pair"] == ["a/b", "a/b"]
    assert cols["force"][0] == 0.5 and math.isnan(cols["force"][1])  # "force" is a number here
    assert reader.measured(cols, "force") == ([1], [0.5])


def test_missing_file(tmp_path):
    assert reader.read_csv(str(tmp_path / "none.csv")) is None
    assert reader.read_csv(str(tmp_path / "none.csv"), missing=[]) == []


def test_summary_accessors():
    s = {"status": "ok", "steps_run": 10, "timing_us": {"step": 100.0, "detect": 3.0, "eliminate": None},
         "window": {"contact_power_ratio": None, "kicked": False},
         "pairs": [{"recall": 0.5, "max_depth_peak": 0.002,
                    "error_vs_reference": {"pos_err_max": 0.003, "gap_max": 0.001, "depth_max": 0.0,
                                           "window": {"pos_err_max": {"mean": 0.002, "max": 0.004, "amplitude": 0.001},
                                                      "gap_max": None}}}]}
    f = reader.window_figures(s)
    assert f["pos_err_max_mm"] == 2.0 and f["pos_err_max_max_mm"] == 4.0 and f["pos_err_final_mm"] == 3.0
    assert math.isnan(f["gap_max_mm"]) and math.isnan(f["contact_power_ratio"])
    assert f["t_contact_us"] == 3.0 and f["t_step_us"] == 100.0 and f["recall"] == 0.5
    assert reader.pair_figures(s)["max_depth_peak_mm"] == 2.0
    assert reader.final_reference_errors(s) == {"pos_err_max": 0.003, "gap_max": 0.001, "depth_max": 0.0}
    x = reader.stability_inputs(s)
    assert x["guard_violations"] == 0 and x["balance_error"] == 0.0 and math.isnan(x["rho"])
    assert reader.pair({}) == {} and reader.final_reference_errors({"pairs": [{}]}) is None


def test_pair_accessors():
    s = {"pairs": [{"tunnelled_peak": {"guest": 2, "host": None}, "recall": 1, "voxel_size_used": 0.004,
                    "window": {"depth_max": {"max": 0.001}, "pos_err_max": {"mean": 9.0}},
                    "error_vs_reference": {"window": {"pos_err_max": {"mean": 0.002, "amplitude": 0.0005}}}}]}
    assert reader.tunnelled_peak(s) == 2
    assert reader.tunnelled_peak({"pairs": [{"tunnelled": 3}]}) == 3 and reader.tunnelled_peak({}) is None
    assert reader.pair_window_stat(s, "pos_err_max", "mean") == 0.002  # the reference's window first
    assert reader.pair_window_stat(s, "depth_max", "max") == 0.001 and reader.pair_window_stat(s, "gap_max", "mean") is None
    assert reader.pair_value(s, "recall") == 1 and reader.pair_value(s, "precision") is None
    assert reader.voxel_size_used(s) == 0.004 and math.isnan(reader.outside_region_peak(s))
    assert reader.tunnelled_both({"pairs": [{"tunnelled": 1, "tunnelled_host": None}]}) == 1.0


def test_run_accessors():
    s = {"stability": {"dt": 1e-4, "integrator": "symplectic_euler"}, "timing_us": {"step": 5.0, "median": 4.0},
         "machine": {"cpu": "x"}, "bodies": [{"name": "a", "nodes": 12}]}
    st = reader.stepping(s)
    assert st["dt"] == 1e-4 and math.isnan(st["dt_crit_min"]) and st["max_substeps"] is None
    assert reader.step_time_us(s) == 5.0 and reader.steps_run_or_none(s) is None
    d = reader.device_timing(s)
    assert d["median_us"] == 4.0 and math.isnan(d["dt"]) and (d["machine_cpu"], d["machine_cores"]) == ("x", "?")
    assert reader.body_nodes(s, "a") == 12 and reader.body_nodes(s, "b") is None
    assert reader.contact(s, strict=False) == {} and reader.contact_bodies(s, strict=False) == (None, None)
    r = {"resolved_scene": {"contacts": [{"host": "h", "guest": "g"}]}}
    assert reader.contact_bodies(r) == ("h", "g") and reader.cpu_check(r) is None
