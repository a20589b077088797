"""scripts/cylinder_bulk.py: the committed cylinder_bulk.csv is what the script makes from the
committed references (results/cylinder_bulk/, results/references/), its level changes are the
distances between the committed levels' surfaces, and its twist is the committed surfaces' (checked
by hand on one row)."""
import csv
import json
import os
import shutil
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RESULTS = os.path.join(ROOT, "results")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import cylinder_bulk  # noqa: E402


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def test_committed_csv_is_what_the_script_makes(tmp_path):
    shutil.copytree(os.path.join(RESULTS, "cylinder_bulk"), tmp_path / "cylinder_bulk",
                    ignore=shutil.ignore_patterns("study"))
    for r in ("cylinder_press", "cylinder_press_one_sided"):
        os.makedirs(tmp_path / "references" / r)
        shutil.copy(os.path.join(RESULTS, "references", r, "surfaces.csv"), tmp_path / "references" / r)
    for f in ("references.csv", "lattice_inversion.csv"):
        shutil.copy(os.path.join(RESULTS, f), tmp_path)
    subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "cylinder_bulk.py"), str(tmp_path)], check=True,
                   capture_output=True)
    assert rows(tmp_path / "cylinder_bulk.csv") == rows(os.path.join(RESULTS, "cylinder_bulk.csv"))


def test_changes_are_the_distances_between_the_levels_surfaces():
    for stem in ("aligned_two", "aligned_one", "alternating_two", "alternating_one", "alternating48_two",
                 "alternating48_one"):
        base = os.path.join(RESULTS, "cylinder_bulk", stem)
        levels = json.load(open(os.path.join(base, "summary.json")))["reference"]["levels"]
        for a, b in zip(levels, levels[1:]):
            sa = cylinder_bulk.load(os.path.join(base, "levels", str(a["level"]), "surfaces.csv"))
            sb = cylinder_bulk.load(os.path.join(base, "levels", str(b["level"]), "surfaces.csv"))
            assert abs(cylinder_bulk.gap(sa, sb) - b["change_max"] * 1e3) < 1e-6, (stem, b["level"])
        # the reference's settled surfaces are its last level's
        last = cylinder_bulk.load(os.path.join(base, "levels", str(levels[-1]["level"]), "surfaces.csv"))
        assert cylinder_bulk.gap(last, cylinder_bulk.load(os.path.join(base, "surfaces.csv"))) < 1e-9


def test_twist_by_hand():
    s = cylinder_bulk.load(os.path.join(RESULTS, "cylinder_bulk", "aligned_two", "surfaces.csv"))["layer"]
    y = {}
    for x, yy, _z, x0, y0, z0 in s:
        if abs(y0) < 1e-9 and abs(z0 - 0.02) < 1e-9 and abs(abs(x0) - 0.025) < 1e-9:
            y[round(x0 * 1e3)] = yy * 1e3
    row = [r for r in rows(os.path.join(RESULTS, "cylinder_bulk.csv"))
           if r["variant"] == "bulk aligned" and r["kind"] == "two-sided"][-1]  # the settled reference
    assert abs(float(row["twist_mm"]) - 0.5 * (y[-25] - y[25])) < 1e-3 * abs(float(row["twist_mm"])) + 1e-9
    assert np.isfinite(float(row["top_z_mm"]))


def test_what_the_report_and_the_docs_say_holds():
    """docs/findings.md and paper/main.tex read these outcomes (the report's figures through
    counts.py's RefCylVol* macros): each statement checked against the CSV."""
    r = rows(os.path.join(RESULTS, "cylinder_bulk.csv"))
    inv = {(x["variant"], x["kind"]): int(x["inverted_rows"]) for x in r if x["kind"].startswith("inversion")}
    assert inv[("springs", "inversion two-sided")] > 0 and inv[("springs", "inversion one-sided")] > 0
    assert all(n == 0 for (v, _k), n in inv.items() if v.startswith("bulk"))

    def last(variant, kind):
        return [x for x in r if x["variant"] == variant and x["kind"] == kind][-1]

    def levels(variant, kind):
        return [x for x in r if x["variant"] == variant and x["kind"] == kind]

    # aligned: neither kind converges, the two settle together, the top row twists
    for k in ("two-sided", "one-sided"):
        assert last("bulk aligned", k)["converged"] == "False"
        assert abs(float(last("bulk aligned", k)["twist_mm"])) > 0.3
    assert float(last("bulk aligned", "one-sided")["kinds_gap_mm"]) < 1e-3
    # alternating: the twist small at every level; one way converges, both ways does not
    assert all(abs(float(x["twist_mm"])) < 0.15 for k in ("two-sided", "one-sided")
               for x in levels("bulk alternating", k))
    assert last("bulk alternating", "one-sided")["converged"] == "True"
    assert last("bulk alternating", "two-sided")["converged"] == "False"
    # alternating and 48 segments: both converge, twist below 0.05 mm, the kinds apart by far less
    # than with the inverting lattice
    fixed = "bulk alternating, cylinder 48 segments"
    for k in ("two-sided", "one-sided"):
        assert last(fixed, k)["converged"] == "True"
        assert all(abs(float(x["twist_mm"])) < 0.05 for x in levels(fixed, k))
    assert float(last(fixed, "one-sided")["kinds_gap_mm"]) < 0.25 * float(last("springs", "one-sided")["kinds_gap_mm"])
