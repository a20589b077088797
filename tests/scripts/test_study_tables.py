"""The committed study tables are what the studies write from the committed CSV files under the
current rules (scripts/study.py --plots-only): helps, useless and the Pareto front included. A rule
changed without the tables written again, or a table edited by hand, fails here."""

import os
import shutil
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
RESULTS = os.path.join(ROOT, "results")
STUDIES = ["accuracy", "ablation", "convergence", "orient", "swap", "region", "detection", "restriction", "regime",
           "bullet", "realtime_grid"]
CSVS = ["accuracy_time.csv", "ablation.csv", "convergence.csv", "orient.csv", "swap.csv", "region.csv", "detection.csv",
        "restriction.csv", "regime.csv", "bullet.csv", "realtime_grid.csv"]
WRITTEN = CSVS + ["defaults.json"] + [os.path.join("tables", n) for n in (
    "accuracy_time.md", "accuracy_time_front.tex", "ablation.md", "ablation_defaults.tex", "convergence.md",
    "orient.md", "swap.md", "region.md", "detection.md", "restriction.md", "regime.md", "bullet.md", "bullet.tex", "bullet_note.tex", "realtime_grid.md")]


def read(path):
    with open(path) as f:
        return f.read()


def test_study_tables_are_written_from_their_csv(tmp_path):
    res = tmp_path / "results"
    (res / "tables").mkdir(parents=True)
    (res / "figures").mkdir()
    for name in CSVS + ["defaults.json"]:
        shutil.copy(os.path.join(RESULTS, name), res / name)
    refs = os.path.join(RESULTS, "references")
    for name in sorted(os.listdir(refs)):  # the references' floors enter the front's noise
        if os.path.isfile(os.path.join(refs, name, "summary.json")):
            (res / "references" / name).mkdir(parents=True)
            shutil.copy(os.path.join(refs, name, "summary.json"), res / "references" / name / "summary.json")
    subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "study.py")] + STUDIES +
                   ["--plots-only", "--results", str(res)], check=True, cwd=ROOT, capture_output=True)
    differ = [n for n in WRITTEN if read(os.path.join(RESULTS, n)) != read(res / n)]
    assert differ == []


def test_bullet_tables_say_how_their_times_were_taken():
    """bullet.{md,tex} label their times untimed and say how many runs went at once, from bullet.csv's
    `jobs` and `machine` (a file without them says it does not know: never a typed "two")."""
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    from harness_results.studies import bullet
    rows = [{"jobs": 2.0, "machine": "Intel(R) Xeon(R) Processor (2 cores)"}]
    assert bullet.timing_note(rows) == ("untimed runs 2 at a time on Intel(R) Xeon(R) Processor (2 cores): "
                                        "the times are indicative only")
    assert "not recorded" in bullet.timing_note([{"jobs": float("nan"), "machine": ""}])
    md = read(os.path.join(RESULTS, "tables", "bullet.md"))
    assert "contact (µs, untimed)" in md and "indicative only" in md


def test_regime_searches_each_scene_with_its_own_forces():
    """The regime search's forces per scene (SCENE_FORCES): the spheres one step below the implant,
    a scene it does not name the implant's list; every force appears in the grid of its scene only."""
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    from harness_results.studies import regime

    class A:
        user = None
    for scene in regime.REGIME_SCENES:
        forces = {f for _e, f, _v, _n, _s in regime.grid(A, scene)}
        assert forces == set(regime.forces_of(scene))
    assert "0.0005" in regime.forces_of("sphere_collision") and "0.01" not in regime.forces_of("sphere_collision")
    assert regime.forces_of("a_users_scene") == regime.FORCES
    assert regime.forces_text(["sphere_collision"]) == "0.0005, 0.001, 0.003 N and `auto` (sphere_collision)"
