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
    assert abs(dt - 1.8e-4) < 1e-15 and args[2:] == ["--set", 'time.guard="substep"'] and float(args[1]) == dt
    assert rg.crit_point(0.0) is None and rg.crit_point(float("nan")) is None
    # with the scene's forcing (the spheres: drivers to step 2400 of 5e-5 s, the second from 2401) the
    # largest dt at or below 0.9 dt_crit that keeps 2400 steps whole: 2400 x 5e-5 / 1048 (0.9 x 1.273e-4 s
    # allows 1047.4 steps)
    doc = {"bodies": [{"drivers": [{"to_step": 2400, "from_step": 1}, {"from_step": 2401, "to_step": -1}]},
                      {"pressure": {"ramp_steps": 0}}]}
    assert rg.forcing_counts(doc) == [2400, 2400]
    dt = rg.crit_point(1.273e-4, 5e-5, rg.forcing_counts(doc))[2]
    assert dt <= 0.9 * 1.273e-4 and abs(2400 * 5e-5 / dt - 1048) < 1e-9
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


def test_a_drifting_point_is_judged_by_its_window_max_and_a_rounded_scene_is_not_the_scene():
    # k1's window mean is within 1.5x but it drifts to 1.6x the baseline's largest error: not kept;
    # k2 ran with a driver's step count rounded by --dt (another scene): not kept, not on the front
    rows = [row("baseline", 1e-4, 1.0, t=50.0), row("k0", 1e-4, 1.0), row("k1", 2e-4, 1.2), row("k2", 4e-4, 1.0)]
    rows[0]["pos_err_max_max_mm"] = 1.0
    rows[2]["pos_err_max_max_mm"] = 1.6
    rows[3]["rounded"] = "bodies.0.drivers.0.to_step: 2400 steps at the scene's time.dt are 37.5 at --dt, rounded to 38"
    chosen = rg.decide(rows)
    by = {r["point"]: r for r in rows}
    assert chosen["point"] == "k0"
    assert by["k1"]["why_not"].startswith("error (window max)") and abs(by["k1"]["max_over_best"] - 1.6) < 1e-12
    assert by["k2"]["why_not"].startswith("not the scene") and not rg.evidence(by["k2"])
    assert rg.rounded_counts({"warnings": ["--dt: a: x", "contacts.0: y"]}) == "a: x"
    # a rounded pressure ramp reaches the same load: kept
    rows[3]["rounded"] = "bodies.1.pressure.ramp_steps: 5000 steps at the scene's time.dt are 312.5 at --dt, rounded to 313"
    assert rg.decide(rows)["point"] == "k2" and rg.evidence(rows[3])


def test_the_front_reads_the_window_max_so_a_swing_is_no_reward():
    # k1 is twice as fast; its window mean is within 10 % of the baseline's error but it swings to
    # 1.8x: on the front beside the baseline (worse and faster), and a swing does not widen the noise
    rows = [row("baseline", 1e-4, 1.0, t=50.0), row("k1", 2e-4, 1.05, t=50.0)]
    rows[0]["pos_err_max_max_mm"], rows[1]["pos_err_max_max_mm"] = 1.0, 1.8
    rg.mark_front(rows, 0.0)
    assert [r["front"] for r in rows] == ["yes", "yes"]
    for r in rows:
        r["pos_err_amp_mm"] = 0.8
    rg.mark_front(rows, 0.0)
    assert [r["front"] for r in rows] == ["yes", "yes"]
    # without the maximum the mean ties the baseline's and the faster k1 alone stays
    rows[1]["pos_err_max_max_mm"] = float("nan")
    rg.mark_front(rows, 0.0)
    assert [r["front"] for r in rows] == ["", "yes"]


def test_a_grid_step_that_would_round_a_drivers_steps_is_brought_down_to_whole_ones():
    doc = {"bodies": [{"drivers": [{"to_step": 2400, "from_step": 1}, {"from_step": 2401, "to_step": -1}]},
                      {"pressure": {"ramp_steps": 5000}}]}
    assert rg.driver_counts(doc) == [2400, 2400]
    # 64 x 5e-5 s would make 2400 steps 37.5: the largest step at or below it with whole ones is 2400 x
    # 5e-5 / 38; 32 x keeps 75 whole steps; no drivers: the step as it is
    assert abs(rg.whole_dt(5e-5, 3.2e-3, rg.driver_counts(doc)) - 2400 * 5e-5 / 38) < 1e-18
    assert rg.whole_dt(5e-5, 1.6e-3, [2400]) == 1.6e-3 and rg.whole_dt(1e-4, 0.0128, []) == 0.0128
