"""The committed study tables are what the studies write from the committed CSV files under the
current rules (scripts/study.py --plots-only): helps, useless and the Pareto front included. A rule
changed without the tables written again, or a table edited by hand, fails here."""

import os
import shutil
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
RESULTS = os.path.join(ROOT, "results")
STUDIES = ["accuracy", "ablation", "convergence", "orient", "swap", "region", "detection", "restriction", "regime"]
CSVS = ["accuracy_time.csv", "ablation.csv", "convergence.csv", "orient.csv", "swap.csv", "region.csv", "detection.csv",
        "restriction.csv", "regime.csv"]
WRITTEN = CSVS + ["defaults.json"] + [os.path.join("tables", n) for n in (
    "accuracy_time.md", "accuracy_time_front.tex", "ablation.md", "ablation_defaults.tex", "convergence.md",
    "orient.md", "swap.md", "region.md", "detection.md", "restriction.md", "regime.md")]


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
