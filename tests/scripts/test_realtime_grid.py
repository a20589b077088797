"""study.py realtime_grid's decision (harness_results/studies/realtime_grid.py): which grid steps keep
the exact method's accuracy, and which is chosen."""
from harness_results.studies import realtime_grid as rg


def row(point, dt, err, cls="steady", status="ok", tunnelled=0, t=100.0):
    return {"point": point, "dt": dt, "pos_err_max_mm": err, "stability_class": cls, "status": status,
            "tunnelled": tunnelled, "t_step_mean_us_t1": t}


def test_the_largest_step_that_keeps_the_accuracy_is_chosen():
    rows = [row("baseline", 1e-4, 1.0, t=50.0), row("k0", 1e-4, 1.0), row("k1", 2e-4, 1.49),
            row("k2", 4e-4, 1.51), row("k3", 8e-4, 1.1, cls="chatters"), row("k4", 1.6e-3, 1.2, tunnelled=3),
            row("k5", 3.2e-3, 1.0, status="failed"), row("k6", 6.4e-3, 1.0, cls="forced")]
    chosen = rg.decide(rows)
    assert chosen["point"] == "k1"
    by = {r["point"]: r for r in rows}
    assert [by[p]["keeps"] for p in ("k0", "k1", "k2", "k3", "k4", "k5", "k6")] == ["yes", "yes", "no", "no", "no", "no", "no"]
    assert by["k2"]["why_not"].startswith("error") and by["k3"]["why_not"] == "chatters"
    assert by["k4"]["why_not"] == "tunnelled" and by["k5"]["why_not"].startswith("status")
    assert by["k6"]["why_not"].startswith("not judged")
    assert by["k1"]["error_over_best"] == 1.49 and by["k0"]["cost_in_explicit_steps"] == 2.0
    assert [r["chosen"] for r in rows].count("yes") == 1 and by["baseline"]["keeps"] == ""


def test_nothing_kept_nothing_chosen():
    rows = [row("baseline", 1e-4, 1.0), row("k0", 1e-4, 2.0), row("k1", 2e-4, float("nan"))]
    assert rg.decide(rows) is None
    assert all(r["chosen"] == "" for r in rows)
    assert rows[2]["why_not"] == "no error measured"


def test_the_front_over_the_step_by_hand():
    # wall s per simulated s: baseline 50e-6/1e-4 = 0.5, k0 1.0, k1 0.5, k2 0.25, k3 0.125 (chatters), k4 0.0625
    # (tunnels). k0 costs more for the same error: off. k1 ties the baseline in time and is within 10 % in
    # error: both stay. k2 is faster and 2x farther: on. k3 and k4 are faster still but not evidence.
    rows = [row("baseline", 1e-4, 1.0, t=50.0), row("k0", 1e-4, 1.0), row("k1", 2e-4, 1.05),
            row("k2", 4e-4, 2.0), row("k3", 8e-4, 3.0, cls="chatters"), row("k4", 1.6e-3, 3.0, tunnelled=3)]
    rg.mark_front(rows, 0.0)
    by = {r["point"]: r for r in rows}
    assert abs(by["k2"]["wall_per_sim_s"] - 0.25) < 1e-12
    assert [by[p]["front"] for p in ("baseline", "k0", "k1", "k2", "k3", "k4")] == ["yes", "", "yes", "yes", "", ""]
    # a reference floor of 1.5 mm makes k2's error equal to the baseline's: k2, now as good and faster, alone
    rg.mark_front(rows, 1.5)
    assert [r["point"] for r in rows if r["front"] == "yes"] == ["k2"]
    # the repeats' ranges: a k2 whose range overlaps the baseline's is no faster, and (worse) drops off
    rows[3]["t_step_mean_range_t1"] = "50-500"
    rg.mark_front(rows, 0.0)
    assert by["k2"]["front"] == ""


def test_the_explicit_point_at_its_critical_step_is_judged_never_chosen():
    # the explicit integrator at 0.9 dt_crit: its dt from the baseline's smallest dt_crit, the guard
    # substepping; judged like a grid point (here it keeps the accuracy at the largest dt) but the
    # chosen step is the largest implicit one
    label, k, dt, integrator, args = rg.crit_point(2e-4)
    assert label == rg.EXPLICIT_CRIT and k == "" and integrator == "symplectic_euler"
    assert abs(dt - 1.8e-4) < 1e-15 and args == ["--dt", "0.00018", "--set", 'time.guard="substep"']
    assert rg.crit_point(0.0) is None and rg.crit_point(float("nan")) is None
    rows = [row("baseline", 1e-4, 1.0, t=50.0), row("k0", 1e-4, 1.0), row("k1", 2e-4, 1.2),
            row(rg.EXPLICIT_CRIT, 1.8e-4, 1.0, t=60.0), row("k2", 4e-4, 2.0)]
    chosen = rg.decide(rows)
    by = {r["point"]: r for r in rows}
    assert by[rg.EXPLICIT_CRIT]["keeps"] == "yes" and by[rg.EXPLICIT_CRIT]["chosen"] == ""
    assert chosen["point"] == "k1"
    assert rg.on_grid(by["k2"]) and not rg.on_grid(by["baseline"]) and not rg.on_grid(by[rg.EXPLICIT_CRIT])
    # on the front: as accurate as the baseline and 0.9 x its wall time per simulated second
    rg.mark_front(rows, 0.0)
    assert abs(by[rg.EXPLICIT_CRIT]["wall_per_sim_s"] - 60e-6 / 1.8e-4) < 1e-12
