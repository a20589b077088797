"""Methods as data (study.py card|accuracy|ablation --method NAME=KEY=JSON,...: harness_results/methods.py),
their recording in the card and the studies' CSV files, the warning and the mark of a run stopped
before its forcing ended (runner.forcing_cut), and the one-line refusal of an interpreter without
numpy and matplotlib (needs.py)."""

import csv
import io
import json
import os
import subprocess
import sys

import pytest

from harness_results import card, methods, needs, reader, runner, writers
from harness_results.studies import common

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
STUDY = os.path.join(ROOT, "scripts", "study.py")


# ---------------------------------------------------------------------------------------------
# The --method parser
def test_commas_inside_json_stay_with_their_value():
    m = methods.parse('k500d=contacts.0.force={"stiffness":500,"damping":0.1},references.solvers=["cgal","fcl"]')
    assert m.name == "k500d"
    assert m.sets == ['contacts.0.force={"stiffness":500,"damping":0.1}', 'references.solvers=["cgal","fcl"]']
    # quotes (a comma and a bracket in a string), nesting, bare words and spaces after a comma
    m = methods.parse('x=contacts.0.detector="a,]b", bodies.0.shape.cells=[[1,2],{"a":[3,4]}],contacts.0.eliminator=plane')
    assert m.sets == ['contacts.0.detector="a,]b"', 'bodies.0.shape.cells=[[1,2],{"a":[3,4]}]',
                      "contacts.0.eliminator=plane"]
    # the recorded cell reads back as the same method
    assert methods.parse("x=" + methods.text(m.sets)) == m
    assert methods.value(m.sets, "bodies.0.shape.cells") == [[1, 2], {"a": [3, 4]}]
    assert methods.value(m.sets, "contacts.0.eliminator") == "plane"
    assert methods.value(m.sets, "contacts.0.two_sided", False) is False


@pytest.mark.parametrize("spec, piece", [
    ("nameonly", "nameonly"),
    ("=contacts.0.force=1", "=contacts.0.force=1"),
    ("x=", "x="),
    ("x=contacts.0.force", "contacts.0.force"),
    ("x=contacts.0.force=[1,2", "unclosed '['"),
    ('x=contacts.0.force={"stiffness":500}}', "unbalanced '}'"),
    ('x=contacts.0.detector="voxel', "unclosed quote"),
    ("x=contacts.0.force=1,,time.dt=1", "''"),
    ("x=.contacts=1", "'.contacts'"),
    ("x=contacts.0.force=1.2.3", "'1.2.3'"),
    ("x=contacts.0.force=[1,]", "'[1,]'"),
    ("two words=time.dt=1", "'two words'"),
])
def test_bad_syntax_names_the_bad_piece(spec, piece):
    with pytest.raises(methods.MethodError) as e:
        methods.parse(spec)
    assert piece in str(e.value) and "\n" not in str(e.value)


def test_names_are_unique_and_not_the_built_ins():
    assert [m.name for m in methods.parse_all(["a=time.dt=1", "b=time.dt=2"])] == ["a", "b"]
    with pytest.raises(methods.MethodError, match="given twice"):
        methods.parse_all(["a=time.dt=1", "a=time.dt=2"])
    with pytest.raises(methods.MethodError, match="built-in"):
        methods.parse_all(["cgal=time.dt=1"], taken=["voxel", "cgal"])
    # a hash of the overrides in the run folder: changed overrides are a new run
    assert methods.folder(methods.parse("a=time.dt=1")) != methods.folder(methods.parse("a=time.dt=2"))


def run_study(*args):
    return subprocess.run([sys.executable, STUDY] + list(args), cwd=ROOT, capture_output=True, text=True)


def test_study_refuses_bad_method_in_one_line_with_exit_2(tmp_path):
    p = run_study("card", "--scene", "sphere_collision", "--out", str(tmp_path), "--harness", "/nonexistent",
                  "--method", 'k=contacts.0.force={"stiffness":500,"damping":0.1},contacts.0.eliminator')
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("study.py: --method") and "'contacts.0.eliminator'" in lines[0]
    p = run_study("convergence", "--method", "k=time.dt=1")  # a study that takes no --method
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and "convergence" in p.stderr
    p = run_study("ablation", "--method", "auto=time.dt=1")  # a column of the grid's name
    assert p.returncode == 2 and "built-in" in p.stderr
    assert os.listdir(tmp_path) == []  # nothing was run


# ---------------------------------------------------------------------------------------------
# The card records the --set overrides and the methods
def fake_row(method, err, overrides=(), forced="no"):
    return {"method": method, "pos_err_max_mm": err, "pos_err_amp_mm": 0.01, "depth_max_mm": 0.1, "stable": "yes",
            "stability": "stable", "why_unstable": "", "tunnelled_total": 0, "t_mean_us": 10.0, "t_p99_us": 20.0,
            "t_max_us": 30.0, "folder": "f_" + method, "overrides": methods.text(overrides), "forced": forced}


def fake_reference(tmp_path):
    ref = tmp_path / "ref"
    ref.mkdir(exist_ok=True)
    src = os.path.join(ROOT, "results", "references", "sphere_collision", "summary.json")
    (ref / "summary.json").write_text(open(src).read())
    return str(ref)


def test_card_records_set_overrides_and_methods(tmp_path):
    sets = ["time.steps=100", 'contacts.0.voxel_size="auto"']
    m = methods.parse('k500d=contacts.0.force={"stiffness":500,"damping":0.1},references.solvers=["cgal","fcl"]')
    rows = [fake_row("voxel", 1.0, ['contacts.0.detector="voxel"'] + sets),
            fake_row(m.name, 0.5, sets + m.sets, forced="yes")]
    base = fake_row(card.NO_FORCE, 5.0, sets)
    out = tmp_path / "card"
    out.mkdir()
    card.write(str(out), "sphere_collision", fake_reference(tmp_path), rows, base, card.judge(rows, base),
               sets, [(m.name, m.sets)])
    got = list(csv.DictReader(io.StringIO((out / "card.csv").read_text())))
    assert [r["method"] for r in got] == ["voxel", "k500d", card.NO_FORCE]
    assert got[1]["overrides"] == methods.text(sets + m.sets)
    assert methods.parse("x=" + got[1]["overrides"]).sets == sets + m.sets  # the cell parses back
    assert got[2]["overrides"] == methods.text(sets)
    assert [r["forced"] for r in got] == ["no", "yes", "no"]
    md = (out / "card.md").read_text()
    assert "`time.steps=100`" in md and "Overrides (`--set`" in md
    assert "Method `k500d` (`--method`)" in md and '{"stiffness":500,"damping":0.1}' in md
    assert "Still forced when they stopped" in md and "k500d" in md.split("Still forced")[1].split("\n")[0]
    assert "| k500d |" in md
    assert (out / "card.png").exists()
    # without --set: said so, not silent
    card.write(str(out), "sphere_collision", fake_reference(tmp_path), rows[:1], base, "s.", [], [])
    assert "none: the scene as written" in (out / "card.md").read_text()
    assert card.plot_note(sets, [(m.name, m.sets)]).count("\n") >= 1 and "k500d (--method)" in card.plot_note(
        sets, [(m.name, m.sets)])


def test_study_csv_columns_only_where_a_method_or_a_forced_run_is(tmp_path):
    cols = ["scene", "config"]
    plain = [{"scene": "s", "config": "c", "forced": ""}]
    assert common.columns_of(cols, plain) == cols  # the committed files stay as they are
    user = plain + [dict(common.user_fields(methods.parse("k=time.dt=1")), scene="s", config="k", forced="yes")]
    assert common.columns_of(cols, user) == cols + ["method", "overrides", "forced"]
    assert common.columns_of(cols, user, ("forced",)) == cols + ["forced"]
    assert common.is_user_row(user[1]) and not common.is_user_row(plain[0])
    assert common.is_user_row({"method": float("nan")}) is False  # an empty column read back as NaN
    text = common.notes(user)
    assert "Methods of the user's (`--method`): k: `time.dt=1`." in text and "Stopped before their forcing ended" in text
    assert common.notes(plain) == ""
    path = str(tmp_path / "study.csv")  # written and read back as --plots-only reads it
    writers.write_csv(path, user, common.columns_of(cols, user))
    back = reader.read_csv(path, text=reader.STUDY_TEXT)
    assert [common.is_user_row(r) for r in back] == [False, True] and back[1]["overrides"] == "time.dt=1"
    assert common.columns_of(cols, back) == cols + ["method", "overrides", "forced"]


def test_user_method_sets_and_labels():
    m = methods.parse('k=contacts.0.force={"stiffness":500,"damping":0.1},contacts.0.two_sided=true')
    assert common.user_method_sets(m)[-2:] == m.sets  # the method's own last: they win
    assert common.resolved_force_label({"force": {"stiffness": 500, "damping": 0.1}}) == "k=500 damping=0.1"
    assert common.resolved_force_label({"force": "auto"}) == "auto"
    assert common.resolved_force_label({"force": 0.01}) == "F=0.01"

    class A:
        user = None
    assert common.user_two_sided(A, "sphere_collision", m) is True
    assert common.user_two_sided(A, "sphere_collision", methods.parse("k=time.dt=1")) is bool(
        common.scene_doc(A, "sphere_collision")["contacts"][0].get("two_sided", False))


# ---------------------------------------------------------------------------------------------
# A run stopped before its forcing ended
def fake_summary(tmp_path, name, after, to=50, end=1200):
    d = tmp_path / name
    d.mkdir()
    s = {"status": "ok", "steps_run": to, "window": {"from_step": 1, "to_step": to, "steps": to,
                                                     "forcing_ends_step": end, "after_forcing": after}}
    (d / "summary.json").write_text(json.dumps(s))
    return str(d), s


def test_forced_run_is_warned_about_once_and_marked(tmp_path):
    cut, s_cut = fake_summary(tmp_path, "cut", False)
    done, s_done = fake_summary(tmp_path, "done", True, to=2000)
    assert runner.forcing_cut(s_cut) == (50, 1200) and runner.forcing_cut(s_done) is None
    assert runner.forcing_cut({"status": "not run"}) is None  # nothing known: nothing said
    err = io.StringIO()
    assert runner.warn_forced(cut, s_cut, err)
    assert not runner.warn_forced(cut, s_cut, err)  # once per run
    assert not runner.warn_forced(done, s_done, err)
    assert err.getvalue() == ("warning: %s stopped at step 50 before its forcing ended at step 1200: its figures are "
                              "of a body still being loaded\n" % cut)
    never = dict(s_cut, window=dict(s_cut["window"], forcing_ends_step=None))
    err = io.StringIO()
    runner.warn_forced(cut + "_never", never, err)
    assert "never ends" in err.getvalue()
    assert runner.forced_text(s_cut) == "yes" and runner.forced_text(s_done) == ""


def test_runner_warns_for_a_cached_forced_run(tmp_path, capsys):
    cut, _ = fake_summary(tmp_path, "cached_cut", False)

    class A:
        harness = "/nonexistent"
        cached_only = False
    runner.harness(A, ["run"], cut)  # cached: not run, its summary read and judged
    assert "warning: %s stopped at step 50 before its forcing ended at step 1200" % cut in capsys.readouterr().err


# ---------------------------------------------------------------------------------------------
# An interpreter without numpy and matplotlib
def test_missing_packages_give_one_line_and_exit_2(monkeypatch, capsys):
    assert needs.missing() == []  # this interpreter has them (the tests' /usr/bin/python3)
    monkeypatch.setattr(needs, "missing", lambda modules=("numpy", "matplotlib"): ["numpy"])
    with pytest.raises(SystemExit) as e:
        needs.numpy_and_matplotlib("study.py")
    assert e.value.code == 2
    assert capsys.readouterr().err == ("study.py: needs numpy and matplotlib (Debian's python3-numpy, "
                                       "python3-matplotlib); run it with /usr/bin/python3 or set PYTHON\n")


def test_entry_points_check_before_importing(tmp_path):
    """study.py, figures.py and plot_bench.py run without numpy: one line, exit 2 (an interpreter
    made blind to numpy by a sitecustomize that hides it)."""
    (tmp_path / "sitecustomize.py").write_text(
        "import sys\nclass Hide:\n    def find_spec(self, name, path=None, target=None):\n"
        "        return None if name.split('.')[0] not in ('numpy', 'matplotlib') else self.fail(name)\n"
        "    def fail(self, name):\n        raise ModuleNotFoundError(name)\n"
        "sys.meta_path.insert(0, Hide())\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    for prog in ["study.py", "figures.py", "plot_bench.py"]:
        p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", prog), "--help"], cwd=ROOT, env=env,
                           capture_output=True, text=True)
        assert p.returncode == 2, (prog, p.stderr)
        assert p.stderr == ("%s: needs numpy and matplotlib (Debian's python3-numpy, python3-matplotlib); run it "
                            "with /usr/bin/python3 or set PYTHON\n" % prog)
