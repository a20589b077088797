"""claims/layer.py: the cylinder's rows and runs made on a layer that resists inversion put in place of
the bundled cylinder's, and the verdicts that read them judged again (claims.md's last section)."""
import csv
import os
import re

import pytest

from harness_results import robustness
from harness_results.claims import layer

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RESULTS = os.path.join(ROOT, "results")


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def test_merge_replaces_the_cylinder_rows_in_place(tmp_path):
    base, fixed, out = tmp_path / "base.csv", tmp_path / "fixed.csv", tmp_path / "out.csv"
    base.write_text("scene,config,x,y\nsphere_collision,a,1,2\ncylinder_press,a,3,4\ncylinder_press,b,5,6\n"
                    "implant_expansion,a,7,8\n")
    fixed.write_text("scene,config,y,z\ncylinder_press_bulk,a,40,9\ncylinder_press_bulk,c,60,9\n")
    assert layer._merge_csv(str(base), str(fixed), str(out)) == 2
    assert out.read_text() == ("scene,config,x,y\nsphere_collision,a,1,2\ncylinder_press,a,,40\ncylinder_press,c,,60\n"
                               "implant_expansion,a,7,8\n")


needs_study = pytest.mark.skipif(not layer.available(RESULTS), reason="results/cylinder_bulk/study not made")


@needs_study
def test_substituted_results_hold_the_fixed_layer(tmp_path):
    sub = layer.substituted(RESULTS, str(tmp_path))
    study = os.path.join(RESULTS, "cylinder_bulk", "study")
    got = [r for r in rows(os.path.join(sub, "accuracy_time.csv")) if r["scene"] == "cylinder_press"]
    want = [r for r in rows(os.path.join(study, "accuracy_time.csv"))]
    assert len(got) == len(want) > 0
    assert [r["pos_err_max_mm"] for r in got] == [r["pos_err_max_mm"] for r in want]
    others = [r for r in rows(os.path.join(RESULTS, "accuracy_time.csv")) if r["scene"] != "cylinder_press"]
    assert [r for r in rows(os.path.join(sub, "accuracy_time.csv")) if r["scene"] != "cylinder_press"] == others
    # the references: the fixed layer's, converged both ways; the two kinds' distance recomputed
    assert os.path.realpath(os.path.join(sub, "references", "cylinder_press")) == \
        os.path.realpath(os.path.join(RESULTS, "cylinder_bulk", "alternating48_two"))
    conv = {r["reference"]: r["converged"] for r in rows(os.path.join(sub, "references.csv")) if r["converged"]}
    assert conv["cylinder_press"] == "True" and conv["cylinder_press_one_sided"] == "True"
    gap = {r["comparison"]: float(r["difference_mm"]) for r in rows(os.path.join(sub, "references_differences.csv"))}
    bulk = [r for r in rows(os.path.join(RESULTS, "cylinder_bulk.csv"))
            if r["variant"] == "bulk alternating, cylinder 48 segments" and r["kinds_gap_mm"]]
    assert gap["cylinder_press: one way against both ways"] == pytest.approx(float(bulk[-1]["kinds_gap_mm"]), abs=1e-3)
    assert os.path.realpath(os.path.join(sub, "runs", "cylinder_press_line")) == \
        os.path.realpath(os.path.join(study, "runs", "cylinder_press_line"))


@needs_study
def test_committed_section_is_what_the_rule_as_written_gives(tmp_path):
    """The counts claims.md and the report give for the fixed layer are the written rule's on the
    substituted results (the first variant; the full 6912 are claims.py's)."""
    records, _results = layer.judge(RESULTS, str(tmp_path), robustness.VARIANTS[:1])
    macros = dict(re.findall(r"\\newcommand\{\\(\w+)\}\{(.*)\}", open(os.path.join(RESULTS, "tables",
                                                                                  "claims_macros.tex")).read()))
    got = {}
    for r in records:
        got.update(dict(r.macros))
    for p in layer.PREFIXES:
        assert macros["RefCylFix%sCounts" % p] == layer.counts_text(got, p)
