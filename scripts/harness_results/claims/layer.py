"""The claims that read the cylinder's rows, judged again with the cylinder on a layer that resists
inversion: a sensitivity of the verdicts to the scene, not a variant of the rule.

The bundled cylinder's two-sided reference does not converge: the layer's top cells invert under
the cylinder (docs/findings.md, "Why the cylinder's two-sided reference does not converge").
experiments/scenes/claims/cylinder_press_bulk.json is the same scene with the fix that converges both
references (effect `bulk`, bulk modulus 1e4 Pa, alternating diagonals, a cylinder of 48 segments;
results/cylinder_bulk.csv). results/cylinder_bulk/study.sh makes its accuracy study and its report
runs into results/cylinder_bulk/study/ against those references (results/cylinder_bulk/alternating48_*,
linked as its references/).

`substituted(root, tmp)` builds in `tmp` a results folder that is `root` with the cylinder's rows and
runs put in place of the bundled cylinder's (the scene named cylinder_press in them): accuracy_time.csv,
accuracy_variants.csv, the references (folders, references.csv and references_differences.csv) and the
report's four cylinder runs. The other files (restriction.csv, detection.csv, realtime.csv, swap.csv)
keep the bundled cylinder's rows: the verdicts that read only them are not judged again. `judge`
judges the claims of CLAIMS on it under every variant of the rule (robustness.VARIANTS).
"""

import csv
import os

from .. import reader, robustness
from ..studies import references as refs_study
from . import judge_all
from .common import Context

SCENE = "cylinder_press"
FIXED = "cylinder_press_bulk"
STUDY = os.path.join("cylinder_bulk", "study")
SCENE_FILE = "experiments/scenes/claims/cylinder_press_bulk.json"
# The claims with a verdict that reads a substituted file, and those verdicts (their macro prefixes).
# (c) is not among them: both its verdicts read restriction.csv where it exists (its exact bound reads
# accuracy_time.csv only without it), and restriction.csv was not made on the fixed layer.
CLAIMS = ["b_episodes", "d_voxel_speed", "completed"]
PREFIXES = ["ClaimB", "ClaimDUnit", "ClaimVE"]
NOT_REMADE = ["restriction.csv", "detection.csv", "realtime.csv", "swap.csv"]
CSVS = ["accuracy_time.csv", "accuracy_variants.csv"]


def study_dir(root):
    return os.path.join(root, STUDY)


def available(root):
    """Whether the fixed layer's accuracy study and report runs are there."""
    d = study_dir(root)
    return (os.path.isfile(os.path.join(d, "accuracy_time.csv")) and
            all(reader.has_summary(os.path.join(d, "runs", "%s_%s" % (k, e))) for k in (SCENE, SCENE + "_f0003")
                for e in ("line", "plane")))


def _rows(path):
    with open(path, newline="") as f:
        r = csv.reader(f)
        head = next(r)
        return head, list(r)


def _merge_csv(base, fixed, out):
    """`base` (a study CSV) with its SCENE rows replaced by `fixed`'s FIXED rows (named SCENE), into
    `out`; the columns are base's (a column fixed lacks is left empty)."""
    head, rows = _rows(base)
    fhead, frows = _rows(fixed)
    si, fsi = head.index("scene"), fhead.index("scene")
    kept = [r for r in rows if r[si] != SCENE]
    new = []
    for fr in frows:
        if fr[fsi] != FIXED:
            continue
        d = dict(zip(fhead, fr))
        d["scene"] = SCENE
        new.append([d.get(c, "") for c in head])
    # the cylinder's place among the scenes as the base file has it
    at = next((i for i, r in enumerate(rows) if r[si] == SCENE), len(rows))
    before = sum(1 for r in rows[:at] if r[si] != SCENE)
    with open(out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(head)
        w.writerows(kept[:before] + new + kept[before:])
    return len(new)


def _link(src, dst):
    os.symlink(os.path.abspath(src), dst)


def substituted(root, tmp):
    """The results folder (in tmp) with the fixed layer's cylinder in place of the bundled one's."""
    d = study_dir(root)
    out = os.path.join(tmp, "results")
    os.makedirs(out)
    special = set(CSVS) | {"references", "references.csv", "references_differences.csv", "runs"}
    for name in os.listdir(root):
        if name not in special:
            _link(os.path.join(root, name), os.path.join(out, name))
    for name in CSVS:
        _merge_csv(os.path.join(root, name), os.path.join(d, name), os.path.join(out, name))
    # references: the fixed layer's two kinds under the bundled cylinder's names
    rdir = os.path.join(out, "references")
    os.makedirs(rdir)
    swap = {SCENE: FIXED, SCENE + "_one_sided": FIXED + "_one_sided"}
    for name in os.listdir(os.path.join(root, "references")):
        src = os.path.join(d, "references", swap[name]) if name in swap else os.path.join(root, "references", name)
        _link(os.path.realpath(src), os.path.join(rdir, name))
    head, rows = _rows(os.path.join(root, "references.csv"))
    ri = head.index("reference")
    fixed_rows = {n: refs_study.reference_rows(n, reader.load_summary(os.path.join(rdir, n))) for n in swap}
    with open(os.path.join(out, "references.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(head)
        done = set()
        for r in rows:
            if r[ri] in swap:
                if r[ri] not in done:
                    done.add(r[ri])
                    w.writerows([[_cell(x.get(c)) for c in head] for x in fixed_rows[r[ri]]])
                continue
            w.writerow(r)
    head, rows = _rows(os.path.join(root, "references_differences.csv"))
    with open(os.path.join(out, "references_differences.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(head)
        for r in rows:
            if r[0] == "%s: one way against both ways" % SCENE:
                dist, n = refs_study.surface_difference(os.path.join(rdir, SCENE), os.path.join(rdir, SCENE + "_one_sided"))
                r = [r[0], "%g" % (1e3 * dist), str(n)]
            w.writerow(r)
    # the report's runs
    os.makedirs(os.path.join(out, "runs"))
    for name in os.listdir(os.path.join(root, "runs")):
        src = os.path.join(root, "runs", name)
        if name.startswith(SCENE + "_"):
            src = os.path.join(d, "runs", name)
            if not os.path.isdir(src):
                continue
        _link(src, os.path.join(out, "runs", name))
    return out


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return "" if v != v else "%g" % v
    return str(v)


def judge(root, tmp, variants=robustness.VARIANTS):
    """(records, results) of CLAIMS on the substituted results (records with their robustness:
    report.with_robustness), results as robustness.judge_variants gives them."""
    from .report import with_robustness
    sub = substituted(root, tmp)
    order = lambda ctx: judge_all(ctx, CLAIMS)  # noqa: E731
    records = order(Context(sub))
    results = robustness.judge_variants(sub, order, Context, variants)
    return with_robustness(records, results), results


def counts_text(m, p):
    return "%s-%s-%s-%s" % tuple(m.get(p + k, "--") for k in ("For", "Against", "Noise", "NotJudged"))


def section(root, base_records, fixed_records, results, title_of):
    """claims.md's section and the report's macros (RefCylFix<prefix>Verdict, ...Counts, ...Robust)."""
    base = {}
    for r in base_records:
        base.update(dict(r.macros))
    fixed = {}
    for r in fixed_records:
        fixed.update(dict(r.macros))
    d = study_dir(root)
    n_conf = sum(1 for r in reader.read_csv(os.path.join(d, "accuracy_time.csv"), missing=[]) if r.get("scene") == FIXED)
    ref_line = []
    for name, kind in ((FIXED, "both ways"), (FIXED + "_one_sided", "one way")):
        s = reader.load_summary(os.path.join(d, "references", name))
        levels, converged = reader.reference_levels(s)
        floor, why = reader.reference_floor(s)
        ref_line.append("%s %s after %d levels (floor %.3g mm: %s)" % (kind, "converged" if converged else "NOT converged",
                                                                      len(levels), 1e3 * floor, why))
    md = ["## The cylinder on a layer that resists inversion (a sensitivity to the scene)", "",
          "The bundled cylinder's two-sided reference does not converge: its layer's top cells invert under the "
          "cylinder (docs/architecture.md). `%s` is the same scene with a layer that resists inversion (effect "
          "`bulk`, bulk modulus 1e4 Pa, alternating diagonals) and a cylinder of 48 segments; its references: %s. "
          "Its accuracy study (%d configurations) and the report's four cylinder runs were made again "
          "(results/cylinder_bulk/study/, `results/cylinder_bulk/study.sh`) and put in place of the bundled "
          "cylinder's; the verdicts that read them are judged again below, under the same %d variants of the rule. "
          "The cylinder's rows of %s were not made again: the verdicts that read them ((c), both its "
          "verdicts: they read restriction.csv; (d) as stated; real time; the swap) are not judged here." % (
              SCENE_FILE, "; ".join(ref_line), n_conf, len(robustness.VARIANTS), ", ".join(NOT_REMADE)), "",
          "| verdict | as stated (the bundled cylinder) | counts | on the fixed layer | counts | robustness on the fixed layer |",
          "|---|---|---|---|---|---|"]
    macros = []
    for p in PREFIXES:
        if p + "Verdict" not in fixed:
            continue
        title = next((title_of(r.key, p, sum(1 for n, _v in r.macros if n.endswith("Verdict")))
                      for r in fixed_records if p + "Verdict" in dict(r.macros)), p)
        md.append("| %s | %s | %s | %s | %s | %s |" % (title, base.get(p + "Verdict", "-"), counts_text(base, p),
                                                     fixed[p + "Verdict"], counts_text(fixed, p), fixed.get(p + "Robust", "-")))
        macros += [("RefCylFix%sVerdict" % p, fixed[p + "Verdict"]), ("RefCylFix%sCounts" % p, counts_text(fixed, p))]
    md += ["", "Counts: for-against-within noise-not judged. robustness.csv does not hold these variants; "
           "results/robustness_layer.csv does (the same columns).", ""]
    return md, macros


def write_csv(root, results):
    """results/robustness_layer.csv: robustness.csv's rows for the fixed layer's verdicts."""
    path = robustness.write_csv(root, [(v, {p: t for p, t in got.items() if p in PREFIXES}) for v, got in results],
                                name="robustness_layer.csv")
    return path
