"""import harness (docs/python.md): scenes, runs, a simulation one can step."""
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import harness

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def cli(harness_bin, *args, cwd=None):
    return subprocess.run([harness_bin, *args], capture_output=True, text=True, cwd=cwd)


# --- scenes ---------------------------------------------------------------------------------

def test_load_bundled_and_file_alike():
    by_name = harness.Scene.load("cylinder_press")
    by_path = harness.Scene.load(os.path.join(ROOT, "experiments", "scenes", "cylinder_press.json"))
    assert by_name.name == by_path.name == "cylinder_press"
    assert by_name.resolved() == by_path.resolved()
    assert by_name.bodies and by_name.contacts and by_name.dt > 0


def test_dict_round_trip_and_edits():
    s = harness.Scene.load("sphere_collision")
    d = s.to_dict()
    again = harness.Scene.from_dict(d, base_dir=os.path.dirname(s.file))
    assert again.resolved() == s.resolved()
    edited = s.with_(**{"contacts.0.force": 0.01, "time.steps": 123})
    assert edited.to_dict()["contacts"][0]["force"] == 0.01 and edited.steps == 123
    assert s.to_dict() == d  # the original is unchanged
    assert s.with_steps(7).steps == 7 and s.with_steps(7).to_dict()["time"]["settle"] is None
    assert s.with_dt_divide(2).dt == pytest.approx(s.dt / 2) and s.with_dt_divide(2).steps == 2 * s.steps


def test_scene_error_is_the_cli_line(harness_bin, capfd):
    s = harness.Scene.load("sphere_collision")
    with pytest.raises(harness.SceneError) as e:
        s.with_(**{"contacts.0.force": -1})
    r = cli(harness_bin, "run", "sphere_collision", "--set", "contacts.0.force=-1", "--out", "/nonexistent/x")
    assert r.returncode == 2
    assert r.stderr.strip() == "harness: error: " + str(e.value)
    assert "contacts.0.force" in str(e.value) and "sphere_collision.json" in str(e.value)
    out, err = capfd.readouterr()
    assert out == "" and err == ""  # nothing printed
    assert isinstance(e.value, ValueError)


@pytest.mark.parametrize("edit, where", [
    ({"contacts.5.force": 1.0}, "contacts.5"),
    ({"time.dt": "fast"}, "time.dt"),
    ({"bodies.0.material.law": "quintic"}, "bodies.0.material.law"),
])
def test_scene_error_names_the_key_path(edit, where):
    with pytest.raises(harness.SceneError, match=where.replace(".", r"\.")):
        harness.Scene.load("sphere_collision").with_(**edit)


def test_from_dict_errors():
    with pytest.raises(harness.SceneError, match=r"^<dict>: time: missing required key"):
        harness.Scene.from_dict({"name": "x"})
    with pytest.raises(harness.SceneError, match=r"^my\.json: .*not a JSON value"):
        harness.Scene.from_dict({"name": float("nan")}, file="my.json")
    with pytest.raises(harness.SceneError, match="no such scene file or bundled scene"):
        harness.Scene.load("no_such_scene")


# --- runs -----------------------------------------------------------------------------------

def test_run_hash_equals_cli(harness_bin, small, tmp_path):
    scene_file = tmp_path / "small.json"
    scene_file.write_text(json.dumps(small.to_dict()))
    base = os.path.dirname(small.file)  # mesh paths: none here, but keep the folder honest
    r = cli(harness_bin, "run", str(scene_file), "--steps", "300", "--quiet", "--out", str(tmp_path / "cli"), cwd=base)
    assert r.returncode == 0, r.stderr
    cli_hash = json.loads((tmp_path / "cli" / "summary.json").read_text())["state_hash"]
    res = harness.run(small, steps=300)
    assert res.exit_code == 0 and res.out is None
    assert res.state_hash == cli_hash
    assert res.summary["steps_run"] == 300
    assert len(res.steps["step"]) == 300 and res.steps["step"][-1] == 300
    assert res.steps["step"].dtype == float and res.steps["pair"].dtype.kind == "U"
    # two threads: the same bits
    assert harness.run(small, steps=300, threads=2).state_hash == cli_hash


def test_run_out_writes_what_the_cli_writes(harness_bin, small, tmp_path):
    scene_file = tmp_path / "small.json"
    scene_file.write_text(json.dumps(small.to_dict()))
    assert cli(harness_bin, "run", str(scene_file), "--steps", "50", "--quiet", "--out", str(tmp_path / "cli")).returncode == 0
    res = harness.run(small, steps=50, out=tmp_path / "py")
    assert res.out == str(tmp_path / "py")
    assert sorted(os.listdir(tmp_path / "py")) == sorted(os.listdir(tmp_path / "cli"))
    for f in ("steps.csv", "timing.csv"):
        assert (tmp_path / "py" / f).read_text().splitlines()[0] == (tmp_path / "cli" / f).read_text().splitlines()[0]
    # the deterministic columns are the same bits; the wall times are in timing.csv, joined by read_steps
    assert (tmp_path / "py" / "steps.csv").read_text() == (tmp_path / "cli" / "steps.csv").read_text()
    assert "t_step_us" in res.steps and len(res.steps["t_step_us"]) == 50


def test_run_accepts_names_and_dicts(small):
    a = harness.run(small.to_dict(), steps=20)
    b = harness.run(small, steps=20)
    assert a.state_hash == b.state_hash
    with pytest.raises(TypeError):
        harness.run(42)


# --- a simulation one can step --------------------------------------------------------------

def test_simulation_hash_equals_cli(harness_bin, small, tmp_path):
    scene_file = tmp_path / "small.json"
    scene_file.write_text(json.dumps(small.to_dict()))
    assert cli(harness_bin, "run", str(scene_file), "--steps", "2100", "--quiet", "--out", str(tmp_path / "c")).returncode == 0
    cli_hash = json.loads((tmp_path / "c" / "summary.json").read_text())["state_hash"]
    sim = harness.Simulation(small)
    sim.step(1000)
    for _ in range(1100):
        sim.step()
    assert sim.step_index == 2100 and sim.time == pytest.approx(2100 * small.dt)
    assert sim.state_hash() == cli_hash


def test_positions_are_views_without_copy(small):
    sim = harness.Simulation(small)
    x = sim.positions("right")
    v = sim.velocities(1)
    assert x.shape == (sim_nodes(small, 1), 3) and v.shape == x.shape
    assert not x.flags.writeable and not x.flags.owndata
    with pytest.raises(ValueError):
        x[0, 0] = 1.0
    before, ptr = x.copy(), x.__array_interface__["data"][0]
    sim.step(10)
    assert np.abs(x - before).max() > 0  # the same array object, changed by the steps
    assert x.__array_interface__["data"][0] == ptr == sim.positions("right").__array_interface__["data"][0]
    # the velocity the driver imposes (-0.05 m/s along x) is seen in place
    assert v[:, 0].min() == pytest.approx(-0.05, rel=0.2)
    del sim  # the view keeps the simulation alive
    assert np.isfinite(x).all()


def sim_nodes(scene, body):
    return harness.Simulation(scene).positions(body).shape[0]


def test_set_positions_moves_a_body(small):
    sim = harness.Simulation(small)
    x0 = sim.positions("left").copy()
    sim.set_positions("left", x0 + [0.0, 0.0, 0.001])
    assert np.allclose(sim.positions("left"), x0 + [0, 0, 0.001], atol=0, rtol=0)
    sim.set_positions("left", x0[:2] - 1e-3, nodes=[0, 1])
    assert np.array_equal(sim.positions("left")[:2], x0[:2] - 1e-3)
    with pytest.raises(ValueError, match=r"shape \(2, 3\)"):
        sim.set_positions("left", x0, nodes=[0, 1])
    with pytest.raises(ValueError, match="not finite"):
        sim.set_positions("left", np.full((1, 3), np.nan), nodes=[0])
    with pytest.raises(KeyError):
        sim.positions("nobody")
    with pytest.raises(IndexError):
        sim.set_positions(0, x0[:1], nodes=[10 ** 6])
    sim.step(5)  # a driver written in Python: the state it set is stepped from
    assert np.isfinite(sim.positions("left")).all()


def test_contacts_penalty_force_is_stiffness_times_depth(small):
    sim = harness.Simulation(small)
    assert len(sim.contacts(0)["node"]) == 0
    sim.step(2300)
    c = sim.contacts("left/right")
    assert len(c["node"]) > 0
    assert set(np.unique(c["way"])) <= {0, 1}
    assert np.allclose(np.linalg.norm(c["direction"], axis=1), 1.0, atol=1e-12)
    inside = c["depth"] > 0
    assert inside.any()
    assert np.allclose(c["force"][inside], 500.0 * c["depth"][inside], rtol=1e-12)
    n_right = sim.positions("right").shape[0]
    assert (c["node"][c["way"] == 0] < n_right).all()
    with pytest.raises(KeyError):
        sim.contacts("no/pair")


@pytest.mark.skipif(not harness.have_reference(), reason="built without FCL and CGAL")
def test_measure_and_energy(small):
    sim = harness.Simulation(small)
    m0 = sim.measure(0)
    assert m0["true_pen_guest"] == 0 and m0["gap"] > 0.003  # 8 mm apart, less the spheres' facets
    sim.step(2300)
    m = sim.measure()
    assert isinstance(m, list) and m[0]["pair"] == "left/right"
    assert m[0]["true_pen_guest"] + m[0]["true_pen_host"] > 0 and m[0]["max_depth"] > 0 and m[0]["gap"] < 0
    e = sim.energy()
    assert abs(e["balance_error"]) < 1e-3  # the audit's balance, as summary.json gives it
    assert e["kinetic"] > 0 and e["dissipated"] > 0


def test_failed_step_keeps_the_last_good_state(small):
    sim = harness.Simulation(small)
    sim.step(3)
    x3, v3 = sim.positions("left").copy(), sim.velocities("left").copy()
    v = v3.copy()
    v[0] = [1e300, 1e300, 1e300]
    sim.set_velocities("left", v)
    with pytest.raises(harness.SimulationError, match=r"^step \d+: .*last good state \(step \d+\)$") as e:
        sim.step(10)
    import re
    failed, good = map(int, re.search(r"^step (\d+):.*\(step (\d+)\)$", str(e.value)).groups())
    assert good == failed - 1 and sim.step_index == good and 3 < failed <= 13
    assert np.isfinite(sim.positions("right")).all()
    sim.set_positions("left", x3)  # the body put back: the simulation steps on
    sim.set_velocities("left", v3)
    sim.step(2)
    assert sim.step_index == good + 2


def test_gil_released_while_stepping(small):
    """Another Python thread runs while step(n) does: it stamps the time in a loop, and stamps fall
    well inside the step's interval (more than Python's 5 ms switch interval from either end)."""
    sim = harness.Simulation(small)
    stamps = []
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            stamps.append(time.perf_counter())

    t = threading.Thread(target=spin)
    t.start()
    time.sleep(0.02)
    t0 = time.perf_counter()
    sim.step(6000)
    t1 = time.perf_counter()
    stop.set()
    t.join()
    assert t1 - t0 > 0.1
    inside = [s for s in stamps if t0 + 0.02 < s < t1 - 0.02]
    assert len(inside) > 1000


def test_ctrl_c_stops_between_steps(small):
    sim = harness.Simulation(small)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        sim.step(2 * 10 ** 6)  # about a minute: stopped after 0.3 s
    assert time.perf_counter() - t0 < 5.0
    k = sim.step_index
    assert 0 < k < 2 * 10 ** 6
    assert np.isfinite(sim.positions(0)).all()
    sim.step(5)  # still usable
    assert sim.step_index == k + 5


def test_interrupted_run_raises(small, tmp_path):
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        harness.run(small, steps=10 ** 7, out=tmp_path / "r")
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # Python's handler is back


# --- the worked example (docs/python.md) ----------------------------------------------------

def test_worked_ablation_runs(tmp_path):
    r = subprocess.run([sys.executable, os.path.join(ROOT, "python", "examples", "ablation.py"),
                        "--steps", "300", "--every", "100", "--forces", "0.003,0.01", "--voxels", "0.0078125",
                        "--out", str(tmp_path)], capture_output=True, text=True, env=os.environ)
    assert r.returncode == 0, r.stderr
    rows = (tmp_path / "ablation.csv").read_text().splitlines()
    assert rows[0].startswith("force,voxel,depth_max_mm") and len(rows) == 1 + 3
    assert (tmp_path / "ablation.png").stat().st_size > 10000


# --- what a referee tried (review of the module) ---------------------------------------------

def test_one_simulation_is_stepped_by_one_thread_at_a_time(small):
    sim = harness.Simulation(small)
    errors = []

    def go():
        try:
            sim.step(1500)
        except RuntimeError as e:
            errors.append(str(e))

    ts = [threading.Thread(target=go) for _ in range(2)]
    [t.start() for t in ts]
    [t.join() for t in ts]
    assert len(errors) == 1 and "another thread" in errors[0]
    assert sim.step_index == 1500
    ref = harness.Simulation(small)
    ref.step(1500)
    assert sim.state_hash() == ref.state_hash()


def test_scene_keeps_its_folder_when_the_working_directory_changes(tmp_path, monkeypatch):
    (tmp_path / "ms" / "sub").mkdir(parents=True)
    # an octahedron as an OFF mesh, the guest of a mesh scene given by a relative path
    (tmp_path / "ms" / "sub" / "octa.off").write_text(
        "OFF\n6 8 0\n0.01 0 0\n-0.01 0 0\n0 0.01 0\n0 -0.01 0\n0 0 0.01\n0 0 -0.01\n"
        "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n")
    doc = {"name": "mesh", "time": {"dt": 1e-5, "steps": 3}, "effects": ["springs"],
           "bodies": [{"name": "o", "shape": {"type": "mesh", "path": "sub/octa.off"}}]}
    (tmp_path / "ms" / "mesh.json").write_text(json.dumps(doc))
    monkeypatch.chdir(tmp_path)
    s = harness.Scene.load("ms/mesh.json")
    d = harness.Scene.from_dict(doc, base_dir="ms")
    import pathlib
    p = harness.Scene.load(pathlib.Path("ms") / "mesh.json")
    monkeypatch.chdir("/")
    for scene in (s, d, p):
        assert harness.run(scene).exit_code == 0
        harness.Simulation(scene).step(2)
    assert s == p and s.resolved() == d.resolved()


def test_scene_error_keeps_bytes_that_are_not_utf8(tmp_path):
    f = tmp_path / "latin1.json"
    f.write_bytes(b'{"name": "M\xfcller", "time": {"dt": 1e-5, "steps": 1}}')
    with pytest.raises(harness.SceneError) as e:
        harness.Scene.load(str(f))
    assert str(e.value).startswith(str(f) + ":1:") and "malformed JSON" in str(e.value)


def test_interrupted_temporary_run_keeps_its_folder(small):
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt) as e:
        harness.run(small, steps=10 ** 7)
    folder = str(e.value).rsplit(" ", 1)[-1]
    assert json.loads(open(os.path.join(folder, "summary.json")).read())["status"] == "interrupted"
    import shutil
    shutil.rmtree(folder)


def test_numpy_values_and_indices(small):
    s = small.with_(**{"time.steps": np.int64(10), "contacts.0.force": {"stiffness": np.float32(250.0)}})
    assert s.steps == 10
    sim = harness.Simulation(s)
    assert sim.positions(np.int64(1)).shape == sim.positions("right").shape
    assert len(sim.contacts(np.int32(0))["node"]) == 0
    sim.set_positions(np.int64(0), sim.positions(0)[:2].copy(), nodes=np.array([0, 1]))


@pytest.mark.parametrize("call, error", [
    (lambda sim, x: sim.positions(2 ** 40), IndexError),
    (lambda sim, x: sim.positions(True), TypeError),
    (lambda sim, x: sim.positions(1.0), TypeError),
    (lambda sim, x: sim.set_positions(0, x[:1], nodes=0), TypeError),
    (lambda sim, x: sim.set_positions(0, x[:1], nodes=[2 ** 40]), IndexError),
    (lambda sim, x: sim.set_positions(0, x[:2], nodes=[0, 0]), ValueError),
    (lambda sim, x: sim.contacts(5), IndexError),
    (lambda sim, x: sim.step(-1), ValueError),
    (lambda sim, x: sim.step(2.5), TypeError),
])
def test_bad_arguments_raise_what_python_raises(small, call, error):
    sim = harness.Simulation(small)
    with pytest.raises(error):
        call(sim, sim.positions(0).copy())
    assert sim.step_index == 0


def test_bad_run_arguments_write_nothing(small, tmp_path):
    with pytest.raises(ValueError, match="threads: must be >= 1"):
        harness.run(small, steps=5, threads=0, out=tmp_path / "a")
    with pytest.raises(ValueError, match="threads: must be >= 1"):
        harness.Simulation(small, threads=0)
    with pytest.raises(TypeError):
        harness.run(small, steps=2.7, out=tmp_path / "b")
    with pytest.raises(harness.SceneError, match="--steps: must be >= 0"):
        harness.run(small, steps=-1, out=tmp_path / "c")
    with pytest.raises(harness.SceneError, match="--compare"):
        harness.run(small, steps=5, compare=tmp_path / "nothing", out=tmp_path / "d")
    assert not any((tmp_path / x).exists() for x in "abcd")


def test_compare_with_a_finished_run(small, tmp_path):
    first = harness.run(small, steps=2300, out=tmp_path / "first")  # in contact from about step 1900
    again = harness.run(small, steps=2300, compare=tmp_path / "first")
    e = again.summary["pairs"][0]["error_vs_reference"]
    assert e["pos_err_max"] == 0.0  # the same run: no distance at all
    other = harness.run(small.with_(**{"contacts.0.force": {"stiffness": 50}}), steps=2300, compare=first.out,
                        out=tmp_path / "other")
    assert other.summary["pairs"][0]["error_vs_reference"]["pos_err_max"] > 0.0
    # a second reference on the same steps: the figures a run compared with it alone gets
    both = harness.run(small.with_(**{"contacts.0.force": {"stiffness": 50}}), steps=2300, compare=first.out,
                       compare_also=other.out)
    assert both.summary["pairs"][0]["error_vs_reference"] == other.summary["pairs"][0]["error_vs_reference"]
    assert both.summary["pairs"][0]["error_vs_reference_also"]["pos_err_max"] == 0.0  # itself
    assert both.summary["pairs"][0]["error_vs_reference_also"]["dir"] == str(other.out)
    with pytest.raises(harness.SceneError, match="--compare-also"):
        harness.run(small, steps=5, compare_also=first.out, out=tmp_path / "e")
    assert not (tmp_path / "e").exists()


def test_views_survive_their_simulation(small):
    sim = harness.Simulation(small)
    sim.step(20)
    x = sim.positions("left")
    kept = x.copy()
    del sim
    others = [harness.Simulation(small) for _ in range(3)]
    for o in others:
        o.step(5)
    assert np.array_equal(x, kept)


def test_scenes_pickle_and_compare(small):
    import pickle
    again = pickle.loads(pickle.dumps(small))
    assert again == small and again.to_dict() == small.to_dict()
    assert small.with_(**{"time.steps": 7}) != small


def test_contacts_of_the_papers_rule_and_both_ways(small):
    s = small.with_(**{"contacts.0.detector": "voxel", "contacts.0.eliminator": "line", "contacts.0.force": 0.003,
                       "contacts.0.two_sided": True})
    sim = harness.Simulation(s)
    sim.step(2300)
    c = sim.contacts(0)
    assert len(c["node"]) > 0
    assert (c["force"] == 0.003).all()  # a constant force per contact
    assert (c["depth"] == 0.0).all()    # the line rule computes no depth (only the penalty and projection do)
    n = {0: sim.positions("right").shape[0], 1: sim.positions("left").shape[0]}
    for way in (0, 1):
        assert (c["node"][c["way"] == way] < n[way]).all()


def test_read_steps_word_columns_without_contacts(tmp_path):
    r = harness.run("hard/exp_large_strain", steps=3)
    assert r.steps["pair"].dtype.kind == "U" and r.steps["detector"].dtype.kind == "U"


def test_node_order_keeps_the_scene_numbering(small):
    """A simulation laid out by locality (node_order, core/node_order.hpp) reads and writes its
    arrays in the scene's numbering: the same rest positions row by row, states that agree to
    rounding before contact, set_positions on the scene's node indices, contacts named alike."""
    for order in ("rcm", "morton"):
        a, b = harness.Simulation(small), harness.Simulation(small, node_order=order)
        for body in a.bodies:
            assert np.array_equal(b.positions(body), a.positions(body))  # at rest: the same node in each row
            assert not b.positions(body).flags.writeable
        x = a.positions("left").copy()
        x[7] += [0.0, 0.0, 1e-3]
        for s in (a, b):
            s.set_positions("left", x[[3, 7]], nodes=[3, 7])
        assert np.array_equal(b.positions("left")[7], a.positions("left")[7])
        a2, b2 = harness.Simulation(small), harness.Simulation(small, node_order=order)
        a2.step(200), b2.step(200)
        for body in a.bodies:
            assert np.abs(b2.positions(body) - a2.positions(body)).max() < 1e-12
    # Contacts at step 2100 (the spheres touch from about 1900): the same nodes, named in the
    # scene's numbering, at the same depths (rows may come in another order).
    a, b = harness.Simulation(small), harness.Simulation(small, node_order="rcm")
    a.step(2100), b.step(2100)
    ca, cb = a.contacts(0), b.contacts(0)
    rows = lambda c: sorted(zip(c["way"].tolist(), c["node"].tolist(), c["depth"].tolist()))
    ra, rb = rows(ca), rows(cb)
    assert len(ra) > 0 and [r[:2] for r in ra] == [r[:2] for r in rb]
    assert max(abs(p[2] - q[2]) for p, q in zip(ra, rb)) < 1e-12
    with pytest.raises(ValueError, match="node_order"):
        harness.Simulation(small, node_order="hilbert")


# --- a response of your own (docs/python.md) ------------------------------------------------

def _touching(small, **edits):
    """`small` two-sided with the plane: the spheres touch from about step 1900; 3000 steps give
    over 1000 steps in contact both ways."""
    return small.with_(**{"contacts.0.two_sided": True, "contacts.0.eliminator": "plane", **edits})


def test_python_penalty_reproduces_the_built_in(small):
    """The built-in linear penalty written in Python (harness.penalty_response) against the rule
    built in, 3000 steps (contacts from about step 1900). Measured: the positions agree within
    4e-17 m (summation order only); the threshold 1e-12 m leaves a margin of 25,000. A penalty 1 %
    too stiff is shown to miss it by far (over 1e-9 m)."""
    scene = _touching(small)
    k = scene.to_dict()["contacts"][0]["force"]["stiffness"]
    built_in = harness.Simulation(scene)
    mine = harness.Simulation(scene, response=harness.penalty_response(k))
    stiffer = harness.Simulation(scene, response=harness.penalty_response(1.01 * k))
    # The scene's force rule is not the response's: under the automatic force the response is
    # given the same pushes (contact normals and depths), so it runs as under the penalty.
    under_auto = harness.Simulation(scene.with_(**{"contacts.0.force": "auto"}), response=harness.penalty_response(k))
    in_contact = 0
    for _ in range(30):
        for s in (built_in, mine, stiffer, under_auto):
            s.step(100)
        in_contact += 100 if len(built_in.contacts()["node"]) else 0
        assert len(mine.contacts()["node"]) == len(built_in.contacts()["node"])
    assert in_contact >= 800

    def gap(a, b):
        return max(np.abs(a.positions(i) - b.positions(i)).max() for i in (0, 1))

    assert gap(built_in, mine) < 1e-12
    assert gap(mine, under_auto) == 0.0
    assert gap(built_in, stiffer) > 1e-9
    # the audit books the response's work as the built-in's
    ea, eb = built_in.energy(), mine.energy()
    assert eb["work_contact"] == pytest.approx(ea["work_contact"], rel=1e-9, abs=1e-15)
    assert ea["work_contact"] != 0.0


def test_python_response_is_given_the_state(small):
    """What the callable receives: both bodies' x, v, m and unit surface normals in the scene's
    numbering, the contacts with the nodes they push against; its forces reach the step."""
    seen = []

    def look(contacts, guest, host):
        seen.append((contacts["pair"], guest["name"], host["name"], len(contacts["node"])))
        for b in (guest, host):
            n = len(b["x"])
            assert b["x"].shape == b["v"].shape == b["normals"].shape == (n, 3) and b["m"].shape == (n,)
            lengths = np.linalg.norm(b["normals"], axis=1)
            assert np.all((np.abs(lengths - 1) < 1e-12) | (lengths == 0)) and (lengths > 0).any()
        assert contacts["h"] > 0 and contacts["hosts"].shape == contacts["weights"].shape == (len(contacts["node"]), 3)
        return None, None  # no force

    sim = harness.Simulation(_touching(small), response={0: look})
    sim.step(2100)
    assert len(seen) >= 2100 and any(n > 0 for *_, n in seen)
    assert seen[0][0] == sim.pairs[0] and set(seen[0][1:3]) == set(sim.bodies)
    np.testing.assert_array_equal(sim.masses(0), harness.Simulation(small).masses(0))


def test_python_response_errors(small):
    def bad_shape(contacts, guest, host):
        return np.zeros((1, 3)), None

    def raises(contacts, guest, host):
        raise ZeroDivisionError("mine")

    with pytest.raises(TypeError, match="callable"):
        harness.Simulation(small, response=42)
    with pytest.raises(KeyError, match="no contact pair"):
        harness.Simulation(small, response={"nope": raises})
    with pytest.raises(harness.SceneError, match=r"time\.integrator.*stiffness"):
        harness.Simulation(small.with_(**{"time.integrator": "implicit_euler"}), response=raises)
    with pytest.raises(harness.SceneError, match=r"contacts\.0.*eliminator.*projection"):
        harness.Simulation(small.with_(**{"contacts.0.eliminator": "projection"}), response=raises)
    sim = harness.Simulation(small, response=raises)
    with pytest.raises(ZeroDivisionError, match="mine"):
        sim.step(3)
    assert sim.step_index == 0  # the last good state
    sim = harness.Simulation(small, response=bad_shape)
    with pytest.raises(ValueError, match=r"shape \(\d+, 3\)"):
        sim.step(1)


def test_add_forces_and_masses_balance_momentum(small):
    """Springs only (no drivers, no damping, no contact yet): a force F on every node of a body for
    one step changes its momentum by n F dt; the audit books the work and stays balanced."""
    scene = small.with_(**{"effects": ["springs"]})
    a, b = harness.Simulation(scene), harness.Simulation(scene)
    m = b.masses("left")
    assert m.shape == (len(b.positions("left")),) and (m > 0).all()
    F = np.array([1e-3, -2e-3, 5e-4])
    b.add_forces("left", np.tile(F, (len(m), 1)))
    a.step(), b.step()
    dp = (m[:, None] * (b.velocities("left") - a.velocities("left"))).sum(axis=0)
    np.testing.assert_allclose(dp, len(m) * F * scene.dt, rtol=1e-9)
    b.step(5)  # the forces were for one step only: no more change of momentum
    a.step(5)
    dp5 = (m[:, None] * (b.velocities("left") - a.velocities("left"))).sum(axis=0)
    np.testing.assert_allclose(dp5, dp, rtol=1e-9)
    e = b.energy()
    assert e["work_external"] != 0.0 and abs(e["balance_error"]) < 1e-9
    with pytest.raises(ValueError, match=r"shape \(2, 3\)"):
        b.add_forces("left", np.zeros((3, 3)), nodes=[0, 1])


def test_set_velocities_books_the_kinetic_change(small):
    """Setting velocities no longer restarts the audit: the kinetic energy's change is work put in."""
    sim = harness.Simulation(small.with_(**{"effects": ["springs"]}))
    sim.step(10)
    before = sim.energy()
    v = np.array(sim.velocities("left"))
    m = sim.masses("left")
    v[:5] *= 2.0
    sim.set_velocities("left", v[:5], nodes=range(5))
    after = sim.energy()
    dk = 0.5 * (m[:5] * (v[:5] ** 2).sum(axis=1)).sum() * (1 - 1 / 4)
    assert after["work_external"] - before["work_external"] == pytest.approx(dk, rel=1e-12)
    assert after["initial"] == before["initial"]
    sim.step(10)
    assert abs(sim.energy()["balance_error"]) < 1e-9


def test_run_with_a_python_response_writes_a_run_folder(small, tmp_path, harness_bin):
    """harness.run(response=...) writes what the command line writes, names the response, and the
    command line compares against it."""
    scene = _touching(small).with_steps(2200)
    k = scene.to_dict()["contacts"][0]["force"]["stiffness"]
    mine = harness.run(scene, response=harness.penalty_response(k), out=tmp_path / "mine")
    assert mine.exit_code == 0 and mine.summary["pairs"][0]["response"] == f"python:penalty_response({k:g})"
    assert mine.summary["stability_verdict"] and len(mine.steps["step"]) > 0
    built = harness.run(scene)
    assert built.summary["pairs"][0]["response"] is None
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene.to_dict()))
    r = cli(harness_bin, "run", str(path), "--out", str(tmp_path / "cmp"), "--quiet", "--compare", str(tmp_path / "mine"))
    assert r.returncode == 0, r.stderr
    cmp = json.loads((tmp_path / "cmp" / "summary.json").read_text())
    assert cmp["compare"]["kind"] == "run"
    with pytest.raises(ZeroDivisionError):
        harness.run(scene, response=lambda c, g, h: 1 / 0, out=tmp_path / "bad")
    assert json.loads((tmp_path / "bad" / "summary.json").read_text())["status"] != "done"
