"""The verdicts' robustness (harness_results/robustness.py): a study row judged again under the rule
as written gives the study's own columns; under a variant, the limits it states; a verdict that a
variant changes is stated fragile, naming the choices behind it; the committed robustness.csv is
what the claims give under each variant."""

import csv
import os

from harness_results import reader, robustness, rules

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
RESULTS = os.path.join(ROOT, "results")
STUDIES = ["accuracy_time.csv", "ablation.csv", "orient.csv", "region.csv", "convergence.csv", "swap.csv", "realtime.csv"]


def test_the_rule_as_written_gives_the_studies_own_columns():
    n = 0
    for name in STUDIES:
        for r in reader.read_csv(os.path.join(RESULTS, name), numbers=(), text=reader.STUDY_TEXT, missing=[]):
            again = rules.reclassify_row(r)
            assert again.get("stability") == r.get("stability"), (name, r)
            if "stable" in r:
                assert again["stable"] == r["stable"], (name, r)
            n += 1
    assert n > 200


def chatter(rho, settled="False"):
    return {"stable": "yes", "stability": "stable", "why_unstable": "", "settled": settled, "contact_power_ratio": rho}


def test_a_variant_moves_the_limits():
    for rho, default, halved, doubled in [(0.005, "stable", "stable", "stable"), (0.015, "marginal", "marginal", "stable"),
                                          (0.025, "marginal", "unstable", "marginal"), (0.05, "unstable", "unstable", "marginal")]:
        with rules.using(rules.DEFAULT):
            assert rules.reclassify_row(chatter(rho))["stability"] == default, rho
        with rules.using(rules.Variant(rho_scale=0.5)):
            assert rules.reclassify_row(chatter(rho))["stability"] == halved, rho
        with rules.using(rules.Variant(rho_scale=2.0)):
            assert rules.reclassify_row(chatter(rho))["stability"] == doubled, rho
    with rules.using(rules.Variant(marginal="stable")):
        r = rules.reclassify_row(chatter(0.015))
        assert r["stability"] == "marginal" and r["stable"] == "yes"
    # a settled run is never marginal; a reason other than the power stands under every limit
    with rules.using(rules.Variant(rho_scale=0.5)):
        assert rules.reclassify_row(chatter(0.015, "True"))["stability"] == "stable"
        grows = dict(chatter(0.001), why_unstable="kinetic energy grows over the window (x3)")
        assert rules.reclassify_row(grows)["stability"] == "unstable"
    assert rules.CURRENT is rules.DEFAULT


def test_fragile_names_the_choices_that_flip_it():
    t = {"for": 3, "against": 0, "noise": 0, "not judged": 0}
    flat = {"for": 1, "against": 0, "noise": 0, "not judged": 2}
    results = [(v, {"ClaimX": ("supported", t) if v.rho_scale != 0.5 else ("inconclusive", flat),
                    "ClaimY": ("not supported", t)}) for v in robustness.VARIANTS]
    s = robustness.summary(results)
    assert robustness.stated_verdict(s["ClaimY"]) == "not supported"
    n = len(robustness.VARIANTS)
    assert robustness.robustness_text(s["ClaimY"]) == "robust: %d of %d variants (no variant moves its counts)" % (n, n)
    assert robustness.stated_verdict(s["ClaimX"]) == "fragile (supported as written)"
    assert robustness.robustness_text(s["ClaimX"]) == (
        "fragile: %d of %d variants agree (2 different counts over the variants; moved by 1 of the 11 choices: "
        "the rho limits); flips to inconclusive in %d (rho limits x0.5)" % (n - n // 3, n, n // 3))
    # flipped by either of two choices: no choice shared, so each that flips it alone is named
    z = [(v, {"ClaimZ": ("inconclusive", flat) if (v.rho_scale == 0.5 or v.window == 0.5) else ("supported", t)})
         for v in robustness.VARIANTS]
    text = robustness.robustness_text(robustness.summary(z)["ClaimZ"])
    assert text.endswith("; alone: rho limits x0.5, window x0.5)"), text
    # flipped only where two choices are made together: both named, and said to act together
    w = [(v, {"ClaimW": ("inconclusive", flat) if (v.rho_scale == 2 and v.marginal == "stable") else ("supported", t)})
         for v in robustness.VARIANTS]
    text = robustness.robustness_text(robustness.summary(w)["ClaimW"])
    assert "(rho limits x2 and marginal counted stable, together" in text, text


def test_the_committed_table_is_what_the_claims_give():
    from harness_results import claims
    from harness_results.claims.common import Context
    path = os.path.join(RESULTS, "robustness.csv")
    if not os.path.isfile(path):  # made by scripts/claims.py, not committed (results/README.md)
        import pytest
        pytest.skip("results/robustness.csv is not there: run scripts/claims.py results first")
    with open(path) as f:
        committed = list(csv.DictReader(f))
    some = robustness.VARIANTS[:1] + [v for v in robustness.VARIANTS if v.rho_scale == 0.5][:2]
    for v, got in robustness.judge_variants(RESULTS, claims.judge_all, Context, some):
        for p, (verdict, t) in got.items():
            row = next(r for r in committed if r["claim"] == p and r["variant"] == v.name())
            assert (row["verdict"], int(row["for"]), int(row["against"]), int(row["noise"]), int(row["not_judged"])) == (
                verdict, t["for"], t["against"], t["noise"], t["not judged"])


def test_rho_over_the_loading_period_by_hand():
    # A study row of the sphere (forcing ends at step 2400, window 1000) that ran 34000 steps: its
    # window starts at 33001, so the old input period is 33000 steps, the loading period 2400.
    row = dict(chatter(0.2838), scene="sphere_collision", steps="34000")
    assert abs(rules.loading_rho(row, 0.2838) - 0.2838 * 2400 / 33000) < 1e-12
    assert rules.loading_rho(dict(row, steps=""), 0.2838) == 0.2838          # its length unknown: as recorded
    assert rules.loading_rho(dict(row, scene="my_scene"), 0.2838) == 0.2838  # not bundled: as recorded
    assert rules.reclassify_row(row)["stability"] == "unstable"              # 0.284 > 0.04
    with rules.using(rules.Variant(rho_norm="loading")):
        assert rules.reclassify_row(row)["stability"] == "marginal"          # 0.0206: within the band (0.01, 0.04]
    # the other way: a row recorded over the loading period, judged over the time before the window
    # (the old normalisation, its limits as calibrated for it): 0.0206 -> 0.2838, unstable
    loaded = dict(row, rho_norm="loading", contact_power_ratio=0.2838 * 2400 / 33000)
    assert rules.reclassify_row(loaded)["stability"] == "marginal"
    assert abs(rules.renormalised_rho(loaded, 0.2838 * 2400 / 33000, "before") - 0.2838) < 1e-12
    with rules.using(rules.Variant(rho_norm="before")):
        assert rules.reclassify_row(loaded)["stability"] == "unstable"
        assert rules.reclassify_row(row)["stability"] == "unstable"          # recorded so already: as it is
    assert rules.renormalised_rho(dict(loaded, steps=""), 0.02, "before") == 0.02  # its length unknown
    # A summary written before input_period_s: converted from its window figures; one written after
    # it: the loading period is what it records, and the old period is converted back.
    w = {"contact_power_W": 2e-4, "energy_in_J": 1e-3, "forcing_ends_step": 2400, "from_step": 33001,
         "after_forcing": True, "contact_power_ratio": 2e-4 * 33000 * 5e-5 / 1e-3}
    s = {"window": w, "resolved_scene": {"time": {"dt": 5e-5}}}
    assert abs(reader.rho_over(s, "loading") - 2e-4 * 2400 * 5e-5 / 1e-3) < 1e-15
    assert reader.rho_over(s, "before") == w["contact_power_ratio"]
    s2 = {"window": dict(w, input_period_s=0.12, contact_power_ratio=0.024), "resolved_scene": s["resolved_scene"]}
    assert reader.rho_over(s2, "loading") == 0.024
    assert abs(reader.rho_over(s2, "before") - 0.33) < 1e-12


def test_an_unforced_run_is_taken_over_its_window():
    # Nothing forces the scene: the new rule takes the energy given at the start over the window
    # (1000 steps), the old one over the 29000 steps before it.
    w = {"contact_power_W": 1e-4, "energy_in_J": 1e-3, "forcing_ends_step": 0, "from_step": 29001, "steps": 1000,
         "after_forcing": True, "contact_power_ratio": 1e-4 * 29000 * 1e-3 / 1e-3}
    s = {"window": w, "resolved_scene": {"time": {"dt": 1e-3}}}
    assert abs(reader.rho_over(s, "loading") - 1e-4 * 1000 * 1e-3 / 1e-3) < 1e-15


def test_moved_by_names_the_choices_that_act_on_a_verdict():
    """A verdict's counts moved by the tie alone: the tie is named, the other nine choices are not,
    however many variants they make."""
    t = {"for": 3, "against": 0, "noise": 0, "not judged": 0}
    u = {"for": 2, "against": 0, "noise": 1, "not judged": 0}
    results = [(v, {"ClaimX": ("supported", t) if v.tie != 0.0 else ("inconclusive", u)}) for v in robustness.VARIANTS]
    assert robustness.moved_by(results, "ClaimX") == ["the relative tie"]
    flat = [(v, {"ClaimX": ("supported", t)}) for v in robustness.VARIANTS]
    assert robustness.moved_by(flat, "ClaimX") == []
    # two choices that act only together: both named (each moves the counts with the other held)
    both = [(v, {"ClaimX": ("inconclusive", u) if (v.window == 2.0 and v.floor == "mesh") else ("supported", t)})
            for v in robustness.VARIANTS]
    assert robustness.moved_by(both, "ClaimX") == ["the noise's floor", "the window's length"]


def test_the_mesh_floor_enters_the_noise_of_the_spheres_only(tmp_path):
    """floor "mesh": the larger of the reference's floor and the scene's mesh floor
    (references_differences.csv), for either kind of reference; a scene without a refined reference
    keeps its floor."""
    from harness_results.claims import common
    (tmp_path / "references_differences.csv").write_text(
        "comparison,difference_mm,vertices\n"
        "\"sphere_collision: mesh refined (x2) against base, at the base vertices\",1.13389,1284\n"
        "\"sphere_collision: one way against both ways\",0.5159,1284\n")
    ctx = common.Context(str(tmp_path))
    assert abs(common.mesh_floor_mm(ctx, "sphere_collision") - 1.13389) < 1e-12
    assert common.mesh_floor_mm(ctx, "cylinder_press") != common.mesh_floor_mm(ctx, "cylinder_press")  # NaN
    orig = reader.reference_floor_mm
    try:
        reader.reference_floor_mm = lambda root, name: {"sphere_collision": 0.0012, "sphere_collision_one_sided": 0.002,
                                                        "cylinder_press": 0.27}[name]
        assert common._kind_floor_mm(ctx, "sphere_collision") == 0.0012
        with rules.using(rules.Variant(floor="mesh")):
            assert common._kind_floor_mm(ctx, "sphere_collision") == 1.13389
            assert common._kind_floor_mm(ctx, "sphere_collision_one_sided") == 1.13389
            assert common._kind_floor_mm(ctx, "cylinder_press") == 0.27
            # two sphere rows 0.5 mm apart: decided under the rule, within the noise with the mesh floor
            a, b = {"pos_err_max_mm": 1.45, "stable": "yes"}, {"pos_err_max_mm": 0.51, "stable": "yes"}
            assert rules.decide(a, b, floor=common._kind_floor_mm(ctx, "sphere_collision")) == rules.WITHIN_NOISE
        assert rules.decide(a, b, floor=common._kind_floor_mm(ctx, "sphere_collision")) == "b"
    finally:
        reader.reference_floor_mm = orig


def test_the_old_normalisation_scales_with_a_runs_dt_divide():
    """A regime row at dt/8 counts 8 times the scene's steps for its forcing and its window: the
    implant (forcing 5000 steps, window 1000) run 208000 steps at dt/8 converts by 200000/40000 = 5,
    as the same run at the scene's dt (26000 steps: 25000/5000), not by 207000/5000."""
    row = dict(chatter(0.0152), scene="implant_expansion", steps="208000", dt_divide="8", rho_norm="loading")
    assert abs(rules.renormalised_rho(row, 0.0152, "before") - 0.0152 * 5.0) < 1e-12
    same = dict(row, steps="26000", dt_divide="1")
    assert abs(rules.renormalised_rho(same, 0.0152, "before") - 0.0152 * 5.0) < 1e-12


def test_a_choice_that_reaches_none_of_a_verdicts_files_is_named_and_not_counted():
    from harness_results.claims import report
    text, attrs = report.not_reached("ClaimARegime")  # regime.csv: the window does not reach it
    assert attrs == ("window",) and "the window's length" in text and "regime.csv" in text
    assert report.not_reached("ClaimA") == ("", ())      # accuracy_time.csv: every choice reaches it
    _t, attrs = report.not_reached("ClaimRTSim")         # realtime.csv: neither window, reference nor stability
    assert set(attrs) == {"window", "reference", "rho_scale", "marginal", "rho_norm"}
    kept = report.reaching([(v, {}) for v in robustness.VARIANTS], attrs)
    assert len(kept) == len(robustness.VARIANTS) // 72 + 1  # 96 of the product and the one made alone
