"""What the claims share: the record each claim returns (Verdict), the results they read (Context:
the runs of scripts/reproduce.sh and the studies' CSV files) and the penetration series of a run."""

import json
import math
import os

from .. import reader, rules, runs

# The scenes of the studies, in the order the claims list them; the exact detectors.
SCENE_ORDER = ["sphere_collision", "cylinder_press", "implant_expansion"]
EXACT = ["hash", "cgal", "fcl"]
NO_FORCE = rules.NO_FORCE


class Verdict:
    """One claim's record. key: its module's name; verdict: "supported", "partly supported", "not
    supported", "inconclusive", "not tested ..." (None for a finding, which has no verdict); md: its
    section of claims.md (lines); macros: [(name, value)] for tables/claims_macros.tex; tex: {file
    name under tables/: text} of its own LaTeX tables; data: whatever else a caller may want; own:
    {verdict prefix: text} for a claim that varies its own thresholds and finds that they change its
    verdict (the text says how): the verdict is then stated fragile whatever the rule's variants say;
    rule_free: the verdict prefixes that no choice of the rule's variants enters (no stability, noise
    or tunnelling): their robustness says the variants do not apply instead of "robust"; rests:
    {verdict prefix: text} for a verdict some of whose comparisons are decisive only by the claim's
    own exception to the evidence rule (exception_text says which and what the general rule gives):
    the verdict table states it beside the verdict."""

    def __init__(self, key, verdict=None, md=(), macros=(), tex=None, data=None, own=None, rule_free=(), rests=None):
        self.key = key
        self.verdict = verdict
        self.md = list(md)
        self.macros = list(macros)
        self.tex = dict(tex or {})
        self.data = data
        self.own = dict(own or {})
        self.rule_free = list(rule_free)
        self.rests = dict(rests or {})

    def __repr__(self):
        return "Verdict(%r, %r)" % (self.key, self.verdict)


_RAW = {}


def read_cached(path, numbers):
    """reader.read_csv(path) once per file version (its path, size and time) for all the Contexts of
    the robustness variants; the rows are shared: copy one before changing it."""
    try:
        st = os.stat(path)
        key = (path, numbers, st.st_size, st.st_mtime_ns)
    except OSError:
        return []
    if key not in _RAW:
        _RAW[key] = reader.read_csv(path, numbers=numbers, text=reader.STUDY_TEXT, missing=[])
    return _RAW[key]


class Context:
    """The results the claims are judged on: root (the results folder), runs (runs.existing_runs),
    by ({scene key: {"title", "force", "scene", eliminator: path}}), steps_run ({(key, elim): steps})."""

    def __init__(self, root):
        self.root = root
        self.runs = runs.existing_runs(root)
        self.by = {}
        for key, scene, title, force, elim, path in self.runs:
            self.by.setdefault(key, {"title": title, "force": force, "scene": scene})[elim] = path
        self.steps_run = {}
        for key, _scene, _title, _force, elim, path in self.runs:
            self.steps_run[(key, elim)] = int(reader.steps_run(reader.load_summary(path)))
        self._csv = {}
        self._base = None

    def csv(self, name, numbers=()):
        """A CSV file of the results (reader.read_csv; `numbers` NaN where the file lacks them); []
        when missing. Each row judged under the current rule (rules.reclassify_row) and marked
        `helps` (yes/no: rules.useful against no_force(scene)) where its scene has a baseline."""
        k = (name, tuple(numbers), id(rules.CURRENT))
        if k not in self._csv:
            rows = [dict(r) for r in read_cached(os.path.join(self.root, name), tuple(numbers))]
            if name == "accuracy_time.csv":  # the window's length and the reference's kind (rules.variant_rows)
                rows = rules.variant_rows(self.root, rows)
            elif rules.CURRENT.reference != rules.OF_ITS_KIND:
                # another study's rows that name their reference and record the two-sided error beside it
                # (ablation.csv): every method against the two-sided reference (its largest
                # position error; the window's other figures stay those against the reference of its kind)
                rows = [rules.as_two_sided(r) for r in rows]
            out = []
            for r in rows:
                r = rules.reclassify_row(r)
                base = self.no_force(r.get("scene"))
                if base is not None and reader.present(r.get("pos_err_max_mm")):
                    r["helps"] = rules.helps_word(r, base)
                out.append(r)
            self._csv[k] = out
        return self._csv[k]

    def no_force(self, scene):
        """{pos_err_max_mm, depth_max_mm} of `scene` with no contact force (accuracy_time.csv's
        NO_FORCE row), None without one."""
        if self._base is None:
            self._base = {scene: {"pos_err_max_mm": reader.num(r.get("pos_err_max_mm"), math.nan),
                                  "depth_max_mm": reader.num(r.get("depth_max_mm"), math.nan),
                                  "reference": r.get("reference"),
                                  "pos_err_max_one_sided_mm": reader.num(r.get("pos_err_max_one_sided_mm"), math.nan),
                                  "pos_err_max_both_ways_mm": reader.num(r.get("pos_err_max_both_ways_mm"), math.nan)}
                          for scene, r in rules.no_force_bases(self.root).items()}
        return self._base.get(scene)

    def window_csv(self, name, numbers=()):
        """csv(name) when it holds the window figures (a `stability` column, scripts/study.py since
        the final window and stability as a rate); [] for an older file: its "stable" and its
        end-of-run errors are not the footing the rules judge on, so its comparisons are not made."""
        rows = self.csv(name, numbers)
        return rows if rows and "stability" in rows[0] else []

    def pairs(self):
        """(key, title, force, line path, plane path) of every setting run with both eliminators."""
        for key, _scene, title, force in runs.SCENES:
            if key not in self.by or "line" not in self.by[key] or "plane" not in self.by[key]:
                continue
            yield key, title, force, self.by[key]["line"], self.by[key]["plane"]

    def shortened_runs(self):
        """Runs that stopped before the step count of their scene file (e.g. --quick)."""
        out = []
        for key, _scene, _title, _force, elim, path in self.runs:
            s = reader.load_summary(path)
            try:
                with open(reader.scene_file(s)) as fh:
                    asked = int(json.load(fh)["time"]["steps"])
            except (OSError, ValueError, KeyError, TypeError):
                continue
            if int(reader.steps_run(s)) < asked:
                out.append("%s_%s" % (key, elim))
        return out


def pen_series(path):
    """A run's truly penetrating nodes (guest + host) on the measured steps: final, peak, sum, how many
    measured, how many with any; residual depth at its peak and at the end."""
    cols = reader.load_steps(path)
    st, g = reader.measured(cols, "true_pen_guest")
    _, h = reader.measured(cols, "true_pen_host")
    _, dep = reader.measured(cols, "max_depth")
    tot = [int(a) + int(b) for a, b in zip(g, h)]
    return {
        "final": tot[-1] if tot else None,
        "peak": max(tot) if tot else None,
        "sum": sum(tot),
        "measured": len(tot),
        "steps_with_pen": sum(1 for v in tot if v > 0),
        "depth_peak": max(dep) if dep else None,
        "depth_final": dep[-1] if dep else None,
    }


def floor_mm(ctx, name, of_kind=False):
    """The floor (mm) of results/references/<name> that the noise takes under the current rule
    (rules.Variant.floor): reader.reference_floor, twice it, the last level's Richardson estimate
    (results/references.csv error_estimate_mm; the floor where there is none), or the larger of the
    floor and the scene's mesh floor (mesh_floor_mm; the floor where there is none). NaN when missing.
    `of_kind`: the rows compared are each against the reference of its kind (accuracy_time.csv's, and a
    study's rows that name it: orient.csv, regime.csv)
    (rules.OF_ITS_KIND): with a one-sided reference <name>_one_sided beside it, both floors
    (rules.KindFloor: a comparison takes the larger of its two rows' references' floors; as a number,
    the larger of the two).
    The other studies measure against the two-sided reference only: its floor."""
    one = _kind_floor_mm(ctx, name)
    if of_kind and rules.CURRENT.reference == rules.OF_ITS_KIND and name + "_one_sided" in _references(ctx):
        other = _kind_floor_mm(ctx, name + "_one_sided")
        return rules.KindFloor({"both ways": one, "one-sided": other}) if not math.isnan(other) else one
    return one


def _references(ctx):
    d = os.path.join(ctx.root, "references")
    return set(os.listdir(d)) if os.path.isdir(d) else set()


def _kind_floor_mm(ctx, name):
    floor = reader.reference_floor_mm(ctx.root, name)
    how = rules.CURRENT.floor
    if how == "double":
        return 2.0 * floor
    if how == "mesh":  # the mesh floor beside the reference's: no figure below it says anything of the shape
        mesh = mesh_floor_mm(ctx, name[:-len("_one_sided")] if name.endswith("_one_sided") else name)
        return floor if math.isnan(mesh) else max(mesh, reader.num(floor, 0.0))
    if how == "richardson":
        est = [reader.num(r.get("error_estimate_mm")) for r in ctx.csv("references.csv")
               if r.get("reference") == name and reader.present(r.get("error_estimate_mm"))]
        return est[-1] if est else floor
    return floor


def reference_converged(ctx, name):
    """Whether results/references/<name> converged (references.csv, its last level's `converged`);
    None when the file does not say."""
    rows = [r for r in ctx.csv("references.csv") if r.get("reference") == name and reader.present(r.get("converged"))]
    if not rows:
        return None
    return str(rows[-1]["converged"]) in ("True", "true", "yes", "1", "1.0")


def scene_cell(ctx, scene, of_kind=False):
    """A scenario's name in a claim's table, marked where a reference its errors are measured
    against did not converge (the errors below its floor are not resolved). `of_kind`: the table's
    rows are accuracy_time.csv's, each method against the reference of its kind: the cost of
    one-sidedness, the kind that did not converge and which methods use it."""
    marks = []
    kinds = [(scene, "")]
    of_kind = of_kind and rules.CURRENT.reference == rules.OF_ITS_KIND
    if of_kind and scene + "_one_sided" in _references(ctx):
        kinds = [(scene, "two-sided ", "the methods both ways"), (scene + "_one_sided", "one-sided ", "the one-sided methods")]
    for k in kinds:
        used = (", used by " + k[2]) if len(k) > 2 else ""
        eq = equilibria(ctx, k[0])
        if eq:
            marks.append("%sreference: %s" % (k[1], eq))
        if reference_converged(ctx, k[0]) is False:
            marks.append("%sreference not converged: floor %.3g mm%s" % (
                k[1], reader.reference_floor_mm(ctx.root, k[0]), used))
        elif "not asymptotic" in _floor_rule(ctx, k[0]):
            # converged by its tolerance, but its changes do not shrink as halving predicts: a jump
            # between levels stays possible (its floor is the larger of its last two changes)
            marks.append("%sreference not in its asymptotic range (%s): floor %.3g mm%s" % (
                k[1], _floor_rule(ctx, k[0]).split("(")[-1].split(":")[0], reader.reference_floor_mm(ctx.root, k[0]),
                used))
    cost = one_sided_cost_mm(ctx, scene)
    if of_kind and not math.isnan(cost):
        marks.insert(0, "one-sidedness alone %.3g mm" % cost)
    return "%s (%s)" % (scene, "; ".join(marks)) if marks else scene


def equilibria(ctx, name):
    """"two equilibria 0.264 mm apart at levels 1 and 2 (each level settles where it is started, ...)"
    where scripts/reference_equilibria.py found that the reference's jump between two levels is a
    switch between equilibria (results/reference_equilibria.csv); "" otherwise."""
    for r in ctx.csv("reference_equilibria.csv"):
        if r.get("reference") == name and r.get("verdict") == "two equilibria":
            return ("two equilibria %.3g mm apart at levels %d and %d (each level settles where it is started, within "
                    "%.2g mm: reference_equilibria.csv)" % (
                        reader.num(r.get("apart_mm")), int(reader.num(r.get("level_a"))), int(reader.num(r.get("level_b"))),
                        max(reader.num(r.get("a_from_b_to_b_mm")), reader.num(r.get("b_from_a_to_a_mm")))))
    return ""


def _floor_rule(ctx, name):
    """Why the floor of results/references/<name> is what it is (reader.reference_floor); ""."""
    path = os.path.join(ctx.root, "references", name)
    return reader.reference_floor(reader.load_summary(path))[1] if reader.has_summary(path) else ""


def mesh_floor_mm(ctx, scene):
    """The scene's mesh floor (mm, references_differences.csv): its reference on the mesh refined once
    against the reference on the scene's mesh, at the scene's vertices (how far the answer moves
    with the discretisation alone); NaN where the scene has no refined reference (the variant
    "mesh" then keeps the reference's floor: robustness.NOT_VARIED says so)."""
    for r in ctx.csv("references_differences.csv"):
        if str(r.get("comparison", "")).startswith(scene + ": mesh refined"):
            return reader.num(r.get("difference_mm"))
    return math.nan


def one_sided_cost_mm(ctx, scene):
    """The scene's one-sided and two-sided references apart (mm, references_differences.csv): what
    one-sidedness alone costs a one-sided method judged against the two-sided limit; NaN without it."""
    for r in ctx.csv("references_differences.csv"):
        if str(r.get("comparison", "")).startswith(scene + ": one way against both ways"):
            return reader.num(r.get("difference_mm"))
    return math.nan


def exception_text(outcomes, general, exception, expected="a"):
    """What a verdict owes to its claim's own exception to the evidence rule (rules.py, verdict:
    "Claims with rules of their own"): `outcomes` as the claim judges them, `general` the same
    comparisons under the general rule (those the exception decides not judged, with why), `exception`
    the exception in words. "" when no comparison rests on it; else "N of its F for and A against
    rest on <exception>; under the general evidence rule: <verdict> (f-a-n-nj)". exception_record
    gives it with the general rule's verdict and counts apart."""
    rec = exception_record(outcomes, general, exception, expected)
    return rec["text"] if rec else ""


def exception_record(outcomes, general, exception, expected="a"):
    """{"text": exception_text's, "general": the general rule's verdict, "counts": "<verdict> (f-a-n-nj)"},
    None when no comparison rests on the exception."""
    moved = [(o, g) for o, g in zip(outcomes, general) if o != g]
    if not moved:
        return None
    n_for = sum(1 for o, _g in moved if o == expected)
    n_against = sum(1 for o, _g in moved if o not in (expected, rules.WITHIN_NOISE) and o not in rules.NOT_JUDGED)
    t = rules.tally(general, expected)
    parts = [x for x in ("%d of its %d for" % (n_for, rules.tally(outcomes, expected)["for"]) if n_for else "",
                         "%d of its %d against" % (n_against, rules.tally(outcomes, expected)["against"]) if n_against else "")
             if x]
    verdict = rules.claim_verdict(general, expected)
    counts = "%s (%d-%d-%d-%d)" % (verdict, t["for"], t["against"], t["noise"], t["not judged"])
    return {"text": "%s rest on %s; under the general evidence rule (those not judged): %s" % (
        " and ".join(parts), exception, counts), "general": verdict, "counts": counts}


def word(outcome, a_name, b_name):
    """An outcome of rules.decide in words: the better one's name, "within noise", "not judged"."""
    if outcome == "a":
        return a_name
    if outcome == "b":
        return b_name
    if outcome == rules.WITHIN_NOISE:
        return "within noise"
    return "not judged (%s)" % outcome


def figure(r, key="pos_err_max_mm", fmt="%.3g"):
    """A row's figure with why it is not evidence (rules.evidence_gap): "1.23", "1.23 (unstable)",
    "1.23 (tunnels)", "1.23 (no better than no force)"; a position error with its reference's kind
    and the other kind's figure beside it (accuracy_time.csv: each method judged against the
    reference of its kind): "1.23 one-sided, 4.56 both ways", "0.5 both ways, 0.9 one-sided"."""
    v = r.get(key)
    if not reader.present(v):
        return "-"
    gap = rules.evidence_gap(r)
    if gap == rules.NOT_STABLE:
        gap = r.get("stability") or gap
    kind = ""
    if key == "pos_err_max_mm" and r.get("reference") == "one-sided" and reader.present(r.get("pos_err_max_both_ways_mm")):
        kind = " one-sided, %s both ways" % (fmt % r["pos_err_max_both_ways_mm"])
    elif key == "pos_err_max_mm" and r.get("reference") == "both ways" and reader.present(r.get("pos_err_max_one_sided_mm")):
        kind = " both ways, %s one-sided" % (fmt % r["pos_err_max_one_sided_mm"])
    return (fmt % v) + kind + ("" if gap is None else " (%s)" % gap)


def verdict_line(label, verdict, outcomes, expected="a", rule=""):
    """The closing line of a claim's section: its verdict, the counts, the rule."""
    t = rules.tally(outcomes, expected)
    return "**Verdict %s: %s** (%s)%s" % (label, verdict, rules.tally_text(t), (". " + rule) if rule else "")


def tally_macros(prefix, verdict, outcomes, expected="a"):
    """The verdict and its counts as macros: <prefix>Verdict, <prefix>For, <prefix>Against,
    <prefix>Noise, <prefix>NotJudged."""
    t = rules.tally(outcomes, expected)
    return [(prefix + "Verdict", verdict), (prefix + "For", str(t["for"])), (prefix + "Against", str(t["against"])),
            (prefix + "Noise", str(t["noise"])), (prefix + "NotJudged", str(t["not judged"]))]
