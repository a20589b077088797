"""scripts/cylinder_levels.py: the cylinder reference's levels made again reproduce the reference
loop's recorded changes (results/references.csv), and the committed cylinder_levels.csv is what the
script makes from the committed surfaces."""
import csv
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RESULTS = os.path.join(ROOT, "results")


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def test_committed_csv_is_what_the_script_makes(tmp_path):
    shutil.copytree(os.path.join(RESULTS, "cylinder_levels"), tmp_path / "cylinder_levels")
    for r in ("cylinder_press", "cylinder_press_one_sided"):
        os.makedirs(tmp_path / "references" / r)
        shutil.copy(os.path.join(RESULTS, "references", r, "surfaces.csv"), tmp_path / "references" / r)
    subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "cylinder_levels.py"), str(tmp_path)], check=True,
                   capture_output=True)
    assert rows(tmp_path / "cylinder_levels.csv") == rows(os.path.join(RESULTS, "cylinder_levels.csv"))


def test_levels_made_again_reproduce_the_recorded_changes():
    loop = {int(r["level"]): float(r["change_mm"]) for r in rows(os.path.join(RESULTS, "references.csv"))
            if r["reference"] == "cylinder_press" and r["change_mm"]}
    change = {(r["from"], r["to"], r["body"]): float(r["max_change_mm"])
              for r in rows(os.path.join(RESULTS, "cylinder_levels.csv")) if r["kind"] == "change"}
    lv = lambda a, b: max(change[(a, b, "layer")], change[(a, b, "cylinder")])
    assert abs(lv("level 2, settled to 1e-5", "level 3, settled to 1e-5") - loop[3]) < 1e-4
    assert abs(lv("level 3, settled to 1e-5", "level 4 (the reference)") - loop[4]) < 1e-4
    # the settling tolerance moves nothing: 1e-6 against 1e-5, far below the level-to-level change
    assert lv("level 2, settled to 1e-5", "level 2, settled to 1e-6") < 1e-3 * loop[3]
    assert lv("level 3, settled to 1e-5", "level 3, settled to 1e-6") < 1e-3 * loop[4]
