"""The judge (scripts/harness_results/judge/): intervals, failures that lose, verdicts from
intervals, the specification table, and the committed SUMMARY.md and claims.md as the judge writes
them, within their lengths."""

import csv
import math
import os
import re
import shutil

import pytest

from harness_results.judge import choices, claims, measure, state

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
RESULTS = os.path.join(ROOT, "results")


class FakeScenes:
    """Floors and spacing as given (mm)."""

    def __init__(self, floor=0.1, spacing=4.0, mesh=1.0):
        self.floor, self.spacing, self.mesh = floor, spacing, mesh

    def floor_mm(self, scene, kind):
        return self.floor

    def spacing_mm(self, scene):
        return self.spacing

    def mesh_floor_mm(self):
        return self.mesh


def row(**kw):
    r = {"scene": "s", "detector": "voxel", "voxel_mm": 8.0, "pos_err_max_mm": 2.0, "pos_err_max_max_mm": 2.2,
         "pos_err_amp_mm": 0.4, "tunnelled": 0, "stability": "stable", "reference": "one-sided",
         "t_contact_us": 10.0, "t_contact_min_us": 9.0, "t_contact_max_us": 12.0}
    r.update(kw)
    return r


def test_side_and_verdict():
    assert claims.side(0.2, 0.9, 1.0, "below") == claims.FOR
    assert claims.side(1.1, 3.0, 1.0, "below") == claims.AGAINST
    assert claims.side(0.9, 1.1, 1.0, "below") == claims.STRADDLES
    assert claims.side(2.5, 3.0, 2.0, "above") == claims.FOR
    assert claims.side(0.5, 1.9, 2.0, "above") == claims.AGAINST
    E = lambda o: claims.Effect("x", 1, 1, 1, 1, "below", outcome=o)  # noqa: E731
    assert claims.verdict_of([E(claims.FOR), E(claims.FOR)]) == claims.SUPPORTED
    assert claims.verdict_of([E(claims.AGAINST)]) == claims.NOT_SUPPORTED
    assert claims.verdict_of([E(claims.FOR), E(claims.STRADDLES)]) == claims.INCONCLUSIVE
    assert claims.verdict_of([]) == claims.NOT_TESTED


def test_interval_is_window_range_and_floor():
    r = measure.measure(row(), choices.DEFAULT, FakeScenes(floor=0.1))
    # window min = max - amp = 1.8; interval [1.8 - 0.1, 2.2 + 0.1]
    assert r.err_lo == pytest.approx(1.7) and r.err_hi == pytest.approx(2.3)
    r2 = measure.measure(row(), choices.Spec(floor="double"), FakeScenes(floor=0.1))
    assert r2.err_lo == pytest.approx(1.6) and r2.err_hi == pytest.approx(2.4)
    r3 = measure.measure(row(), choices.Spec(floor="mesh"), FakeScenes(floor=0.1, mesh=1.0))
    assert r3.err_lo == pytest.approx(0.8) and r3.err_hi == pytest.approx(3.2)
    assert (r.t, r.t_lo, r.t_hi) == (10.0, 9.0, 12.0)


def test_stability_from_the_error_motion_against_the_stated_length():
    sc = FakeScenes(floor=0.1, spacing=4.0)
    # a grid detector: L = max(voxel 8, floor 0.1, spacing/4 1) = 8 mm
    assert measure.measure(row(pos_err_amp_mm=7.9), choices.DEFAULT, sc).cls == "steady"
    r = measure.measure(row(pos_err_amp_mm=8.1), choices.DEFAULT, sc)
    assert r.cls == "chatters" and r.failed.startswith("chatters") and r.cls_from == "error motion"
    # an exact detector: no voxel, L = spacing/4 = 1 mm
    assert measure.measure(row(detector="cgal", pos_err_amp_mm=1.2), choices.DEFAULT, sc).cls == "chatters"
    assert measure.measure(row(detector="cgal", pos_err_amp_mm=0.9), choices.DEFAULT, sc).cls == "steady"
    # L halved and doubled
    assert measure.measure(row(pos_err_amp_mm=5), choices.Spec(chatter_length="half"), sc).cls == "chatters"
    # the edge share for every detector: L = spacing/4 = 1 mm for the grid too
    assert measure.measure(row(pos_err_amp_mm=1.2), choices.Spec(chatter_length="edge"), sc).cls == "chatters"
    # an unstable run compared when unstable runs do not fail
    assert measure.measure(row(pos_err_amp_mm=9), choices.Spec(unstable_fails=False), sc).failed == ""
    # the C++ class wins where the row records it
    assert measure.measure(row(pos_err_amp_mm=9, stability_class="steady"), choices.DEFAULT, sc).cls == "steady"
    assert measure.measure(row(stability_class="grows"), choices.DEFAULT, sc).failed == "grows"


def classed(**kw):
    """A row with its C++ class and the figures it was decided on (a grid detector, L the voxel)."""
    r = row(stability_class="steady", chatter_amp_mm=4.0, chatter_length_mm=7.8, chatter_length_from="voxel",
            injection_share=0.015, kinetic_growth=1.2, kinetic_max_J=1e-6, growth_floor_J=1e-3)
    r.update(kw)
    return r


def test_the_class_again_from_its_figures_under_the_specification():
    sc = FakeScenes()
    sc.stated_edge_mm = lambda scene: 1.0
    # as written: the run's class, from the run
    r = measure.measure(classed(), choices.DEFAULT, sc)
    assert (r.cls, r.cls_from, r.length) == ("steady", "run", 7.8)
    # the chatter length: the edge share the scene's exact runs state (1 mm), or the stated L halved
    r = measure.measure(classed(), choices.Spec(chatter_length="edge"), sc)
    assert (r.cls, r.cls_from, r.length) == ("chatters", "run's figures", 1.0) and r.failed.startswith("chatters")
    assert measure.measure(classed(), choices.Spec(chatter_length="half"), sc).cls == "chatters"
    assert measure.measure(classed(), choices.Spec(chatter_length="double"), sc).cls == "steady"
    # the injection share: 1.5 % injects against 1 %, a recorded injects is steady against 5 %
    assert measure.measure(classed(), choices.Spec(contact_input_share=0.01), sc).cls == "injects"
    assert measure.measure(classed(stability_class="injects", injection_share=0.03), choices.Spec(
        contact_input_share=0.05), sc).cls == "steady"
    # ... or grows where its kinetic energy grew above the floor, or chatters beyond L
    assert measure.measure(classed(stability_class="injects", injection_share=0.03, kinetic_growth=3.0,
                                   kinetic_max_J=1e-2), choices.Spec(contact_input_share=0.05), sc).cls == "grows"
    assert measure.measure(classed(stability_class="injects", injection_share=0.03, chatter_amp_mm=9.0),
                           choices.Spec(contact_input_share=0.05), sc).cls == "chatters"
    # settled, forced and failed stay; a row without the figures keeps its class whatever the choice
    assert measure.measure(classed(stability_class="settled", chatter_amp_mm=9.0), choices.Spec(
        chatter_length="edge"), sc).cls == "settled"
    assert measure.measure(row(stability_class="steady", pos_err_amp_mm=5.0), choices.Spec(
        chatter_length="edge"), sc).cls == "steady"


def test_the_committed_classes_are_their_figures_under_the_choices_as_written():
    """Every accuracy row that records the class's figures gets its C++ class back from them."""
    data = claims.Data(RESULTS)
    rows = [r for r in data.csv("accuracy_time.csv") if isinstance(r.get("chatter_length_from"), str)
            and r.get("chatter_length_from")]
    assert len(rows) > 100
    for r in rows:
        assert measure.run_class(r, choices.DEFAULT, data.scenes)[0] == r["stability_class"], (r["scene"], r["config"])
    assert set(data.scenes.edge) == {"sphere_collision", "cylinder_press", "implant_expansion"}


def test_failures_tunnelling_and_blow_ups():
    sc = FakeScenes()
    assert measure.measure(row(tunnelled=3), choices.DEFAULT, sc).failed == "3 nodes through"
    assert measure.measure(row(tunnelled=3), choices.Spec(tunnel_limit=10), sc).failed == ""
    assert "blew up" in measure.measure(row(stability="failed", why_unstable="guard"), choices.DEFAULT, sc).failed


def test_a_one_sided_method_fails_on_the_guests_nodes_through_alone():
    """Issue 54: a guest node through the host fails any method; a host node through the guest fails
    a method that acts both ways and is reported beside a one-sided one, where the row records the
    count by body; a row without the split keeps the count together."""
    sc = FakeScenes()
    host_only = dict(tunnelled=2, tunnelled_guest=0, tunnelled_host=2)
    one = measure.measure(row(two_sided="no", eliminator="line", **host_only), choices.DEFAULT, sc)
    assert one.failed == "" and one.host_beside == 2
    both = measure.measure(row(two_sided="yes", eliminator="line", **host_only), choices.DEFAULT, sc)
    assert both.failed == "2 nodes through" and both.host_beside == 0
    guest = measure.measure(row(two_sided="no", tunnelled=3, tunnelled_guest=1, tunnelled_host=2),
                            choices.DEFAULT, sc)
    assert guest.failed == "1 nodes through"
    # a count that fell over the window is laid on the guest: the window's 5 less the host's 2 at the end
    fell = measure.measure(row(two_sided="no", tunnelled=5, tunnelled_guest=0, tunnelled_host=2),
                           choices.DEFAULT, sc)
    assert fell.failed == "3 nodes through"
    assert measure.measure(row(two_sided="no", tunnelled=2), choices.DEFAULT, sc).failed == "2 nodes through"
    # the grid's line and plane push the guest alone where the row does not say (regime.csv)
    assert measure.one_sided({"detector": "voxel", "eliminator": "plane"})
    assert not measure.one_sided({"detector": "cgal", "eliminator": "line"})


def test_the_committed_split_reproduces_the_tunnelled_count():
    """accuracy_time.csv's rows that record the nodes through by body: the guest's and the host's at the
    end never exceed the window's largest count, and a one-sided row is judged on the guest's."""
    with open(os.path.join(RESULTS, "accuracy_time.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r.get("tunnelled_guest", "") != ""]
    assert rows
    for r in rows:
        assert float(r["tunnelled_guest"]) + float(r["tunnelled_host"]) <= float(r["tunnelled"])
        through, beside = measure.nodes_through(r)
        assert through == (float(r["tunnelled_guest"]) if r["two_sided"] == "no" else float(r["tunnelled"]))


def test_a_failing_run_loses_and_two_are_not_compared():
    sc = FakeScenes(floor=0.0)
    good = measure.measure(row(pos_err_max_mm=5.0, pos_err_max_max_mm=5.0, pos_err_amp_mm=0.0), choices.DEFAULT, sc,
                           label="good")
    bad = measure.measure(row(pos_err_max_mm=1.0, tunnelled=2), choices.DEFAULT, sc, label="bad")
    # the failing run has the smaller error and still loses
    assert claims.error_ratio(good, bad, "x", "").outcome == claims.FOR
    assert claims.error_ratio(bad, good, "x", "").outcome == claims.AGAINST
    assert claims.error_ratio(bad, bad, "x", "") is None
    # both ok: the ratio and its interval by hand: 5 / [1.8, 2.2] -> against below 1
    other = measure.measure(row(), choices.DEFAULT, sc)
    e = claims.error_ratio(good, other, "x", "")
    assert e.value == pytest.approx(2.5) and e.lo == pytest.approx(5 / 2.2) and e.hi == pytest.approx(5 / 1.8)
    assert e.outcome == claims.AGAINST
    # a time claim never compares a failing run
    assert claims.time_ratio(bad, good, "x", "", 2.0) is None
    t = claims.time_ratio(good, other, "x", "", 0.5, extra_a=10.0)
    assert t.value == pytest.approx(2.0) and t.lo == pytest.approx(19 / 12) and t.hi == pytest.approx(22 / 9)


def write_csv(path, rows):
    cols = sorted({k for r in rows for k in r})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)


def implant(elim, force, err, tunnelled=0, voxel=8.0):
    return row(scene="implant_expansion", eliminator=elim, force=force, pos_err_max_mm=err, pos_err_max_max_mm=err,
               pos_err_amp_mm=0.0, tunnelled=tunnelled, voxel_mm=voxel)


def test_claim_a_follows_the_data(tmp_path):
    """The plane's best against the line's: supported when the plane is better beyond the noise,
    not supported when the numbers are swapped, and a line that always fails loses."""
    def judged(rows):
        write_csv(str(tmp_path / "accuracy_time.csv"), rows)
        write_csv(str(tmp_path / "regime.csv"), [{"scene": "none"}])
        return claims.claim_a(claims.Data(str(tmp_path)), choices.DEFAULT)
    res = judged([implant("plane", "F=0.01", 5.0), implant("line", "F=0.01", 20.0)])
    assert res.verdict == claims.SUPPORTED and res.effects[0].value == pytest.approx(0.25)
    res = judged([implant("plane", "F=0.01", 20.0), implant("line", "F=0.01", 5.0)])
    assert res.verdict == claims.NOT_SUPPORTED
    res = judged([implant("plane", "F=0.01", 50.0), implant("line", "F=0.01", 5.0, tunnelled=1400)])
    assert res.verdict == claims.SUPPORTED and math.isnan(res.effects[0].value)
    # the automatic force is apart unless pooled
    rows = [implant("plane", "F=0.01", 20.0), implant("line", "F=0.01", 30.0), implant("line", "auto", 1.0)]
    assert judged(rows).verdict == claims.SUPPORTED
    write_csv(str(tmp_path / "accuracy_time.csv"), rows)
    assert claims.claim_a(claims.Data(str(tmp_path)), choices.Spec(auto_force="pooled")).verdict == claims.NOT_SUPPORTED


def test_choices_table_is_one_declarative_table():
    names = [c.name for c in choices.CHOICES]
    assert len(names) == len(set(names))
    for c in choices.CHOICES:
        assert c.why and c.alternatives and all(w for w in c.alternatives.values())
    assert choices.DEFAULT.name() == "as written"
    with pytest.raises(KeyError):
        choices.Spec(no_such_choice=1)
    for key, names_ in state.REACHES.items():
        assert set(names_) <= set(choices.BY_NAME), key


def copy_results(dst):
    """The files the judge reads, copied from results/."""
    os.makedirs(dst)
    for f in os.listdir(RESULTS):
        if f.endswith(".csv"):
            shutil.copy(os.path.join(RESULTS, f), dst)
    shutil.copytree(os.path.join(RESULTS, "runs"), os.path.join(dst, "runs"),
                    ignore=shutil.ignore_patterns("frames", "*.vtk", "*.pvd"))
    for ref in os.listdir(os.path.join(RESULTS, "references")):
        src = os.path.join(RESULTS, "references", ref)
        if os.path.isdir(src):
            os.makedirs(os.path.join(dst, "references", ref))
            for f in ("summary.json", "surfaces.csv"):
                if os.path.exists(os.path.join(src, f)):
                    shutil.copy(os.path.join(src, f), os.path.join(dst, "references", ref))


def test_committed_statements_are_the_judges(tmp_path):
    """SUMMARY.md, claims.md, specifications.csv and the report's claim files, as committed, are what
    the judge writes from the committed data (rerun scripts/claims.py results after a change)."""
    out = str(tmp_path / "r")
    copy_results(out)
    state.write_all(out)
    for f in ("SUMMARY.md", "claims.md", "specifications.csv", "tables/claims_macros.tex", "tables/claims_verdicts.tex"):
        with open(os.path.join(out, f)) as a, open(os.path.join(RESULTS, f)) as b:
            assert a.read() == b.read(), "results/%s is not what scripts/claims.py writes" % f


def words(text):
    return len(re.findall(r"\S+", text))


def test_the_answer_first_and_short():
    with open(os.path.join(RESULTS, "SUMMARY.md")) as f:
        summary = f.read()
    assert words(summary) <= 600
    assert summary.count("\n|---") == 1, "SUMMARY.md has one table"
    with open(os.path.join(RESULTS, "claims.md")) as f:
        detail = f.read()
    assert words(detail) <= 6000
    for para in re.split(r"\n\s*\n", detail):
        if para.lstrip().startswith("|"):
            for line in para.splitlines():
                for cell in line.strip().strip("|").split("|"):
                    assert words(cell) <= 40, "a table cell of claims.md over 40 words: %s" % cell[:80]
        else:
            assert words(para) <= 120, "a paragraph of claims.md over 120 words: %s" % para[:80]


def test_an_ensemble_widens_the_interval_and_decides_the_class():
    """A row the ensemble study ran again: its interval spans the members' window ranges, and it
    fails when most members are unstable (a class that flips is not one class)."""
    class Ens(FakeScenes):
        def __init__(self, ens):
            super().__init__(floor=0.1)
            self.ens = ens

        def ensemble_of(self, row):
            return self.ens
    ens = {"members": 5, "stability_verdict": "flips", "classes": "chatters:2;steady:3", "failed_members": 0,
           "pos_err_max_mm": 2.0, "pos_err_max_min_mm": 1.5, "pos_err_max_max_mm": 2.6, "tunnelled_max": 0}
    r = measure.measure(row(), choices.DEFAULT, Ens(ens))
    assert r.cls == "flips" and r.failed == "" and r.cls_from == "ensemble of 5"
    assert r.err_lo == pytest.approx(1.4) and r.err_hi == pytest.approx(2.7)
    r = measure.measure(row(), choices.DEFAULT, Ens(dict(ens, classes="chatters:3;steady:2")))
    assert r.failed == "unstable in 3 of 5 members"
    r = measure.measure(row(), choices.DEFAULT, Ens(dict(ens, tunnelled_max=2)))
    assert r.failed == "2 nodes through"
    assert measure.ensemble_key(dict(row(), _file="f.csv", voxel_mm=8.0)) == \
        measure.ensemble_key(dict(row(), voxel_mm="8"), row_file="f.csv")
    # a one-sided method's members: the guest's nodes through fail it, the host's are reported beside
    split = dict(ens, classes="steady:5", tunnelled_max=2, tunnelled_guest_max=0, tunnelled_host_max=2)
    r = measure.measure(row(two_sided="no", eliminator="line"), choices.DEFAULT, Ens(split))
    assert r.failed == "" and r.host_beside == 2
    r = measure.measure(row(two_sided="yes", eliminator="line"), choices.DEFAULT, Ens(split))
    assert r.failed == "2 nodes through"
    # restriction.csv's projection with and without its bound are two configurations
    assert measure.ensemble_key(dict(row(), response="projection")) != \
        measure.ensemble_key(dict(row(), response="projection + exact bound"))


def test_the_ensemble_study_keeps_its_rows_and_names_each_configuration(tmp_path):
    """study.py ensemble: the rows already in ensembles.csv stand (only the missing runs are made), and
    restriction.csv's two projections get folders of their own."""
    from harness_results.studies import ensemble
    r = {"_file": "restriction.csv", "scene": "s", "config": "cgal", "eliminator": "projection",
         "force": "positions", "voxel_mm": float("nan"), "two_sided": "no"}
    assert ensemble.folder_of(dict(r, response="projection")) != \
        ensemble.folder_of(dict(r, response="projection + exact bound"))
    path = os.path.join(RESULTS, "ensembles.csv")
    kept = ensemble.committed(path)
    with open(path) as f:
        assert len(kept) == len(list(csv.DictReader(f)))
    assert ensemble.committed(str(tmp_path / "none.csv")) == {}


def test_a_universal_claim_is_refuted_by_one_case():
    E = lambda o: claims.Effect("x", 1, 1, 1, 1, "below", outcome=o)  # noqa: E731
    assert claims.verdict_of([E(claims.FOR), E(claims.AGAINST)]) == claims.INCONCLUSIVE
    assert claims.verdict_of([E(claims.FOR), E(claims.AGAINST)], universal=True) == claims.NOT_SUPPORTED


def test_claim_c_counts_a_restriction_by_its_bound(tmp_path):
    """(c) as written: only the restrictions that compute the bound; projection alone, read as a
    restriction, costs what the penalty does and reverses the verdict."""
    def r(resp, t, lo, hi, bound=""):
        return {"scene": "sphere_collision", "detector": "cgal", "response": resp, "stability": "stable",
                "pos_err_max_mm": 1.0, "pos_err_amp_mm": 0.0, "tunnelled": 0, "t_contact_us": t,
                "t_contact_min_us": lo, "t_contact_max_us": hi, "t_bound_us": bound}
    write_csv(str(tmp_path / "restriction.csv"), [r("penalty", 10, 9, 12), r("projection", 10, 9, 11),
                                                   r("projection + exact bound", 10, 9, 11, 290),
                                                   r("volume (LDI bound)", 100, 90, 110)])
    data = claims.Data(str(tmp_path))
    res = claims.claim_c(data, choices.DEFAULT)
    assert res.verdict == claims.SUPPORTED
    e = res.effects[0]  # the cheapest with a bound: the volume, 100 / 10
    assert e.value == pytest.approx(10.0) and e.lo == pytest.approx(90 / 12) and e.hi == pytest.approx(110 / 9)
    res = claims.claim_c(data, choices.Spec(restriction_bound="not required"))
    assert res.verdict == claims.NOT_SUPPORTED and res.effects[0].value == pytest.approx(1.0)


def test_claim_e_is_recall_under_every_deformation(tmp_path):
    rows = [{"deformation": d, "force": "F=0", "region": "full", "margin": 0, "recall": rec, "outside_peak": 0}
            for d, rec in (("wrap", 1.0), ("inflation", 0.9))]
    write_csv(str(tmp_path / "region.csv"), rows)
    data = claims.Data(str(tmp_path))
    assert claims.claim_e(data, choices.DEFAULT).verdict == claims.NOT_SUPPORTED
    assert claims.claim_e(data, choices.Spec(e_miss=0.05)).verdict == claims.NOT_SUPPORTED
    write_csv(str(tmp_path / "region.csv"), [dict(x, recall=0.97) if x["deformation"] == "inflation" else x for x in rows])
    assert claims.claim_e(claims.Data(str(tmp_path)), choices.Spec(e_miss=0.05)).verdict == claims.SUPPORTED


def test_reversals_name_the_specification():
    base = claims.Result("x", "t", "p", "d", [claims.Effect("s", 2, 1.5, 2.5, 1, "above")])
    other = claims.Result("x", "t", "p", "d", [claims.Effect("s", 0.5, 0.4, 0.6, 1, "above")])
    same = claims.Result("x", "t", "p", "d", [claims.Effect("s", 2.1, 1.5, 2.5, 1, "above")])
    spec = choices.Spec(tunnel_limit=10)
    revs = state.reversals([(choices.DEFAULT, base), (choices.DEFAULT, same), (spec, other)])
    assert len(revs) == 1 and revs[0][0] is spec
    assert state.stated(base, revs) == "supported (fragile)"


def test_claim_sim_reads_the_implicit_grid(tmp_path):
    """(sim): where the implicit grid has the scene its points alone are read (one timing session;
    the real-time study's rows were timed on another day, its implicit rows before the contact was in
    the implicit system); a point beyond 1.5x the best error does not count."""
    def rt(mode, integrator, factor, over, stability="stable"):
        return {"scene": "sphere_collision", "method": "cgal", "mode": mode, "threads": 1, "integrator": integrator,
                "realtime_factor_mean": factor, "realtime_factor_p99": factor / 2, "error_over_best": over,
                "pos_err_max_mm": 1.0, "pos_err_amp_mm": 0.0, "tunnelled": 0, "stability": stability,
                "status": "ok"}

    def pt(dt, factor, over, cls="steady", integrator="implicit_euler"):
        return {"scene": "sphere_collision", "method": "cgal", "integrator": integrator, "dt": dt,
                "realtime_factor_mean_t1": factor, "realtime_factor_p99_t1": factor / 2, "error_over_best": over,
                "pos_err_max_mm": 1.0, "tunnelled": 0, "stability_class": cls, "status": "ok"}
    write_csv(str(tmp_path / "realtime.csv"), [rt("scene dt", "symplectic_euler", 0.2, 1.0),
                                               rt("implicit Euler, 10 dt", "implicit_euler", 5.0, 1.2)])

    def effect(grid):
        write_csv(str(tmp_path / "realtime_grid.csv"), grid or [{"scene": "none"}])
        return claims.claim_sim(claims.Data(str(tmp_path)), choices.DEFAULT).effects[0]
    assert effect([]).value == pytest.approx(5.0)  # no grid: the study's own implicit row stands
    e = effect([pt(1e-4, 0.5, 1.4), pt(2e-4, 3.0, 2.0)])  # the stale row goes; 3.0 is too inaccurate
    assert e.value == pytest.approx(0.5) and "grid" in e.note and e.outcome == claims.AGAINST
    assert effect([pt(1e-4, 1.2, 1.4), pt(2e-4, 4.0, 1.3, cls="chatters")]).value == pytest.approx(1.2)
    # the study's explicit row (0.2, another session) is not read beside the grid; the grid's own explicit point is
    assert effect([pt(1e-4, 0.1, 1.4)]).value == pytest.approx(0.1)
    e = effect([pt(1e-4, 0.1, 1.4), pt(5e-5, 0.3, 1.0, integrator="symplectic_euler")])
    assert e.value == pytest.approx(0.3) and "explicit" in e.note
    # a point the grid does not keep (here: a driver's steps rounded, not the scene's loading) does not count
    assert effect([pt(1e-4, 0.1, 1.4), dict(pt(2e-4, 0.4, 1.0), keeps="no")]).value == pytest.approx(0.1)


def test_claim_c_a_failing_run_loses():
    """(c) with c_failures=lose: every restriction fails and the penalty does not -> for the claim; the
    penalty fails and a restriction does not -> against; both fail -> not compared."""
    def run(failed, t=10.0):
        return measure.Run({}, "r", failed, "steady", "run", 1.0, 0.9, 1.1, t, t, t, 1.0)
    pen_ok, pen_bad = run(""), run("injects")
    assert claims.failure_effect("s/voxel", pen_ok, [("volume", run("3 nodes through"))]).outcome == claims.FOR
    assert claims.failure_effect("s/voxel", pen_bad, [("volume", run(""))]).outcome == claims.AGAINST
    assert claims.failure_effect("s/voxel", pen_bad, [("volume", run("3 nodes through"))]) is None
    assert claims.failure_effect("s/voxel", pen_ok, [("volume", run("")), ("projection", run("x"))]) is None
