"""What the studies share: the scenes, the settings swept, the --set overrides of a configuration,
and a run's row (its window figures with the stability judgement)."""

import json
import math
import os
import subprocess
import tempfile

from .. import methods, reader, rules, runner, writers

SCENES = ["sphere_collision", "cylinder_press", "implant_expansion"]
# The paper's eliminator for each scenario (line for the spheres and the cylinder, plane for the implant).
PAPER_ELIMINATOR = {"sphere_collision": "line", "cylinder_press": "line", "implant_expansion": "plane"}
# Each scene's own voxel size (the studies that keep it: swap, region).
SCENE_VOXEL = {"sphere_collision": 0.004, "cylinder_press": 0.008, "implant_expansion": 0.008}
PENALTY = '{"stiffness":500}'
CONSTANT = "0.01"
# Every run of every study is measured by CGAL every STUDY_EVERY steps (and scripts/reproduce.sh's
# runs too): one sampling rule, so that recall and the window figures mean the same everywhere.
STUDY_EVERY = 10
# Errors above this (1 m) are runs that blew up: drawn at the top edge (or capped) in the figures.
PARETO_CAP_MM = 1000.0


# ---------------------------------------------------------------------------------------------
# The scenes a study runs: the bundled three, or one scene of the user's (study.py --scene FILE|NAME
# --out DIR: a.user, set by set_user_scene) with its own eliminator, footing voxels and reference.
def scenes(a):
    """The scenes' names this study runs (and the rows of its CSV are keyed by)."""
    return [a.user["name"]] if getattr(a, "user", None) else SCENES


def scene_arg(a, scene):
    """What `harness run` is given for a scene: the user's file, or the bundled name."""
    user = getattr(a, "user", None)
    return user["path"] if user and scene == user["name"] else scene


def paper_eliminator(a, scene):
    """The paper's eliminator of a bundled scene; a user's scene's own (contacts.0.eliminator)."""
    user = getattr(a, "user", None)
    return user["eliminator"] if user and scene == user["name"] else PAPER_ELIMINATOR[scene]


def footing_voxels(a, scene, bundled):
    """The voxels at and above the host's node spacing: `bundled` (a study's table) for the bundled
    scenes; for a user's scene the smallest power of two at or above the host's mean surface edge
    (the harness's `auto` voxel) and twice it."""
    user = getattr(a, "user", None)
    return user["footing"] if user and scene == user["name"] else bundled[scene]


def set_user_scene(a, scene, out, reference=None, voxel=None):
    """study.py --scene: a.user for `scene` (a file or bundled name), every output in `out` (a.results),
    the reference `reference`, else out/references/<name> (made by the study that needs it); the
    footing voxels `voxel` (m) and twice it, else the harness's `auto` voxel and twice it."""
    name = reader.scene_name(scene)
    with tempfile.TemporaryDirectory() as tmp:  # the auto voxel of the voxel detector, from a 0-step run
        subprocess.run([a.harness, "run", scene, "--steps", "0", "--quiet", "--out", tmp,
                        "--set", 'contacts.0.detector="voxel"', "--set", 'contacts.0.voxel_size="auto"',
                        "--set", "references.solvers=[]", "--set", "output.frames_every=0"],
                       check=True, stderr=subprocess.DEVNULL)
        s = reader.load_summary(tmp)
    v = voxel if voxel else reader.num(reader.pair_value(s, "voxel_size_used"))
    contact = reader.contact(s, strict=False)
    elim = contact.get("eliminator", "line")
    a.results = out
    a.user = {"name": name, "path": os.path.abspath(scene) if os.path.isfile(scene) else scene,
              "eliminator": elim if elim in ("line", "plane") else "line", "footing": [v, 2 * v],
              "reference": reference or os.path.join(out, "references", name), "doc": reader.resolved(s),
              "bodies": (contact.get("host"), contact.get("guest"))}
    for d in ["figures", "tables"]:
        os.makedirs(os.path.join(out, d), exist_ok=True)
    return a.user


def scene_doc(a, scene):
    """The scene's document: the user's (resolved), or the bundled file's."""
    user = getattr(a, "user", None)
    return user["doc"] if user and scene == user["name"] else reader.bundled_scene(scene)


def pair_bodies(a, scene, bundled):
    """(host, guest) of the scene's first pair: `bundled` (a study's table) or the user's scene's."""
    user = getattr(a, "user", None)
    return tuple(user["bodies"]) if user and scene == user["name"] else bundled[scene]


def scene_voxel(a, scene):
    """The voxel size a study keeps for the scene: SCENE_VOXEL, or the user's footing voxel."""
    return footing_voxels(a, scene, {k: [v] for k, v in SCENE_VOXEL.items()})[0]


def reference_dir(a, scene):
    """The folder of a scene's reference: the user's, or --results/references/<scene>."""
    user = getattr(a, "user", None)
    return user["reference"] if user and scene == user["name"] else os.path.join(a.results, "references", scene)


def one_sided_reference_dir(a, scene):
    """The folder of a scene's one-sided reference (`harness reference --one-sided`: the references
    study's <scene>_one_sided beside reference_dir); it may not exist."""
    return reference_dir(a, scene).rstrip("/") + "_one_sided"


def reference_of_kind(a, scene, two_sided):
    """(kind, its folder, the other kind's folder or None) of the reference a method is judged
    against: the one-sided reference for a one-sided method where it exists, the two-sided one
    otherwise (and for a method both ways); kind "one-sided" or "both ways"."""
    both, one = reference_dir(a, scene), one_sided_reference_dir(a, scene)
    has_one = os.path.exists(os.path.join(one, "surfaces.csv"))
    if two_sided or not has_one:
        return "both ways", both, one if has_one else None
    return "one-sided", one, both


KIND_KEY = {"one-sided": "one_sided", "both ways": "both_ways"}


def with_both_kinds(row, s, kind):
    """`row` (the error run `s`'s figures against the reference of `kind`) given its kind and its
    largest position error against both kinds of reference (pos_err_max_one_sided_mm,
    pos_err_max_both_ways_mm): the other from the second reference the run measured beside the first
    (reference_kind.also_reference; NaN where none was). Returns row."""
    from .. import reference_kind
    row["reference"] = kind
    row["pos_err_max_%s_mm" % KIND_KEY[kind]] = row["pos_err_max_mm"]
    other = "one-sided" if kind == "both ways" else "both ways"
    also = reference_kind.also_reference(s)
    row["pos_err_max_%s_mm" % KIND_KEY[other]] = figures(also)["pos_err_max_mm"] if also is not None else float("nan")
    return row


def reference_floor_mm(a, scene):
    """The floor (mm) of the scene's reference (reader.reference_floor; reference_dir); 0 without one."""
    path = reference_dir(a, scene)
    if not reader.has_summary(path):
        return 0.0
    return 1e3 * reader.reference_floor(reader.load_summary(path))[0]


def kind_floor_mm(a, scene):
    """The floors (mm) of the two kinds of reference (reference_of_kind) as a rules.KindFloor (a
    comparison takes the larger of its two rows' references' floors); the two-sided reference's
    alone where there is no one-sided one."""
    both = reference_floor_mm(a, scene)
    one = one_sided_reference_dir(a, scene)
    if reader.has_summary(one):
        f = 1e3 * reader.reference_floor(reader.load_summary(one))[0]
        if not math.isnan(f):
            return rules.KindFloor({"both ways": both, "one-sided": f})
    return both


def no_force_bases(a):
    """{scene: its run without contact force} in --results (rules.no_force_bases)."""
    return rules.no_force_bases(a.results)


def mark_useless(a, rows, bases=None):
    """rules.mark_useless against `bases`, by default the scenes' runs without contact force
    (no_force_bases): every row gets its helps and useless columns. Returns rows."""
    return rules.mark_useless(rows, no_force_bases(a) if bases is None else bases)


def force_label(f):
    """A force setting as the tables name it: auto, k=<stiffness> (penalty), F=<newtons> (constant)."""
    if f == "auto":
        return "auto"
    if f.startswith("{"):
        return object_force_label(json.loads(f))
    return "F=%s" % f


def object_force_label(f):
    """An object force as the tables name it: k=<stiffness>, then its other keys (a rule of the
    registry other than the penalty: rule="hertz" exponent=1.5)."""
    rest = " ".join("%s=%s" % (k, json.dumps(v)) for k, v in sorted(f.items()) if k != "stiffness")
    return ("k=%g" % f["stiffness"] if "stiffness" in f else "") + (" " if rest and "stiffness" in f else "") + rest


def force_setting(label):
    """The contacts.0.force value of a label (force_label's inverse; defaults.json holds labels)."""
    if label == "auto":
        return "auto"
    if label.startswith("k="):
        return json.dumps({"stiffness": float(label[2:])})
    return label[2:]


def config_sets(det, voxel, elim, force, extra):
    """The --set overrides of one configuration: detector, eliminator, force, one-sided contact, CGAL
    every STUDY_EVERY steps, the voxel size when given, then `extra`."""
    sets = ['contacts.0.detector="%s"' % det, 'contacts.0.eliminator="%s"' % elim, "contacts.0.force=" +
            (json.dumps(force) if force == "auto" else force), "contacts.0.two_sided=false",
            'references.solvers=["cgal"]', "references.every=%d" % STUDY_EVERY]
    if voxel:
        sets.append("contacts.0.voxel_size=%g" % voxel)
    return sets + extra


def folder_name(scene, label, elim, force):
    return "%s/%s_%s_%s" % (scene, label.replace(" ", "_").replace(",", ""), elim, force_label(force))


def figures(s):
    """A run's row: its window figures (reader.window_figures), the figures its C++ class was decided on
    (reader.class_figures: chatter amplitude and length, injection share, growth), its stability columns from its C++
    class (rules.stability_fields: stable, stability, stability_class, what the claims' judge reads,
    judge/measure.py; why_unstable) and `forced` ("yes" for a run stopped before its forcing ended:
    runner.forcing_cut)."""
    return dict(reader.window_figures(s), forced=runner.forced_text(s), **reader.class_figures(s),
                **rules.stability_fields(s))


# ---------------------------------------------------------------------------------------------
# The user's methods (study.py --method NAME=KEY=JSON,...: harness_results/methods.py) and the runs
# stopped before their forcing ended, in a study's rows.
def user_methods(a):
    """The --method methods of study.py (methods.Method: name, sets); [] without any."""
    return list(getattr(a, "user_methods", None) or [])


def user_method_sets(m):
    """The --set overrides of a user's method in a study: CGAL every STUDY_EVERY steps (as every
    study's run), then the method's own (which may change them): the scene as written otherwise."""
    return ['references.solvers=["cgal"]', "references.every=%d" % STUDY_EVERY] + list(m.sets)


def user_two_sided(a, scene, m):
    """Whether a user's method detects both ways: its contacts.0.two_sided override, else the scene's
    (its first pair's two_sided, false when it does not say: the scene format's default)."""
    doc = scene_doc(a, scene) or {}
    pair = (doc.get("contacts") or [{}])[0]
    return bool(methods.value(m.sets, "contacts.0.two_sided", pair.get("two_sided", False)))


def resolved_force_label(c):
    """The force of a run's resolved first pair as the tables name it (force_label; an object's other
    keys beside its stiffness)."""
    f = c.get("force")
    if isinstance(f, dict):
        return object_force_label(f)
    if f is None:
        return ""
    return force_label(f if isinstance(f, str) else json.dumps(f))


OPTIONAL_COLUMNS = ("method", "overrides", "forced", "stability_class", "timings")
# The figures the C++ class was decided on (reader.class_figures), after the optional columns where
# the runs recorded them.
CLASS_COLUMNS = ("chatter_amp_mm", "chatter_length_mm", "chatter_length_from", "injection_share", "kinetic_growth",
                 "kinetic_max_J", "growth_floor_J")


def is_user_row(r):
    """Whether a study's row is a user's method's (its `method` names one; a built-in row's is empty)."""
    return isinstance(r.get("method"), str) and bool(r.get("method"))


def user_fields(m):
    """The columns a user's method's rows carry: method (its name) and overrides (methods.text)."""
    return {"method": m.name, "overrides": methods.text(m.sets)}


# The nodes through at the end by body (reader.window_figures): the judge fails a one-sided method on
# the guest's alone (judge/measure.py nodes_through).
SPLIT_COLUMNS = ("tunnelled_guest", "tunnelled_host")


def columns_of(cols, rows, optional=OPTIONAL_COLUMNS):
    """A study's CSV columns: `cols`, then those of `optional` (OPTIONAL_COLUMNS) some row fills (method and
    overrides, the user's method's name and overrides on its rows and empty on the built-in ones,
    where a --method added rows; forced where a run was stopped before its forcing
    ended; stability_class where the runs carry the C++ class; timings where --classes-only kept
    the committed timings, committed_timings), then CLASS_COLUMNS where the runs recorded the figures
    their class was decided on: the files of runs without them are as they were."""
    out = list(cols) + [c for c in optional if c not in cols and
                        any(isinstance(r.get(c), str) and r.get(c) for r in rows)]
    if any(r.get("chatter_length_from") for r in rows):  # the runs recorded their class's figures
        out += [c for c in CLASS_COLUMNS if c not in out]
    if any(reader.present(r.get(c)) for r in rows for c in SPLIT_COLUMNS):  # the nodes through by body
        out += [c for c in SPLIT_COLUMNS if c not in out]
    return out


def notes(rows, name="config"):
    """The lines a study's Markdown adds under its tables: the user's methods with their overrides,
    and the rows whose runs were stopped before their forcing ended; "" when there are none."""
    out = []
    seen = []
    for r in rows:
        if is_user_row(r) and r["method"] not in [m for m, _ in seen]:
            seen.append((r["method"], r.get("overrides")))
    if seen:
        out.append("Methods of the user's (`--method`): " + "; ".join("%s: `%s`" % (m, o) for m, o in seen) + ".")
    forced = [r for r in rows if r.get("forced") == "yes"]
    if forced:
        out.append("Stopped before their forcing ended (column `forced`: `--quick` or `--steps` cut them short; their "
                   "figures are of a body still being loaded): %s." % ", ".join(
                       sorted({" ".join(str(r.get(k, "")) for k in ("scene", name) if r.get(k) not in (None, ""))
                               for r in forced})))
    return "".join("\n" + line + "\n" for line in out)


def pooled(timed):
    """Over timing repeats that each did the same work: the step's and the collision unit's pooled
    mean (the mean of the repeats' means: equal step counts) and the median of the repeats' 99th
    percentiles, µs, and the machine as the first run recorded it (NaN / "" without runs)."""
    d = [reader.step_distribution(s) for s in timed]
    nan = float("nan")
    return {"t_step_mean_us": sum(x["step_mean_us"] for x in d) / len(d) if d else nan,
            "t_step_p99_us": rules.median([x["step_p99_us"] for x in d]),
            "t_contact_mean_us": sum(x["contact_mean_us"] for x in d) / len(d) if d else nan,
            "t_contact_p99_us": rules.median([x["contact_p99_us"] for x in d]),
            # the unit's response part alone (a response that uses no detected contact: the volume restriction)
            "t_eliminate_mean_us": sum(x["eliminate_mean_us"] for x in d) / len(d) if d else nan,
            "t_eliminate_p99_us": rules.median([x["eliminate_p99_us"] for x in d]),
            "t_eliminate_median_us": rules.median([x["eliminate_median_us"] for x in d]),
            "machine": d[0]["machine"] if d else ""}


def timing_runs(summaries):
    """The timing repeats of runner.repeated's runs that ran (a repeat not run, study.py --cached-only,
    or refused has no time); the error run where there are none."""
    return [s for s in summaries[1:] if reader.status(s) not in ("not run", "refused")] or summaries[:1]


# study.py --classes-only: the error runs made again (the binary as it stands: every run then carries
# the C++ stability class), the timings kept from the committed file. The same states give the same
# errors: a row whose error does not reproduce its committed twin's to the digits the file keeps is
# reported, and its timings are not kept (they would describe other runs).


def committed_timings(a, name, rows, keys):
    """With --classes-only, each row's timing columns (t_*_us and their ranges, repeats, machine) taken
    from its committed twin in results/NAME (the same `keys`), where the row's pos_err_max_mm and
    tunnelled reproduce the twin's; rows stamped `timings` ("committed" or why not). Returns the rows;
    prints the rows that do not reproduce. Without --classes-only the rows as they are."""
    if not getattr(a, "classes_only", False):
        return rows
    old = read_rows(a, name) or []
    key = lambda r: tuple(str(r.get(k, "")) for k in keys)  # noqa: E731
    twins = {key(r): r for r in old}
    for r in rows:
        t = twins.get(key(r))
        if t is None:
            r["timings"] = "no committed twin: timings of the error run"
            continue
        # as the file writes them (writers.cell: six digits), the error and the tunnelled nodes
        e, e0 = reader.num(r.get("pos_err_max_mm")), reader.num(t.get("pos_err_max_mm"))
        same = writers.cell(e) == writers.cell(e0) and \
            writers.cell(reader.num(r.get("tunnelled"), 0.0)) == writers.cell(reader.num(t.get("tunnelled"), 0.0))
        if not same:
            r["timings"] = "error %s mm does not reproduce the committed %s mm: timings of the error run" % (e, e0)
            print("study: %s %s: %s" % (name, " / ".join(key(r)), r["timings"]))
            continue
        for c, v in t.items():
            if c.startswith("t_") or c in ("repeats", "machine"):
                r[c] = v
        r["timings"] = "committed"
    return rows


def combine(summaries):
    """A configuration's row from runner.repeated's runs: the errors of the first (the error run);
    the timings from the others (the timing repeats, each the same work, run one at a time; the
    error run's own where there are none): contact and step time per step, the median of the
    repeats' medians and their range (min, max), the pooled mean and the median of the repeats'
    99th percentiles, and the machine as the runs recorded it."""
    f = figures(summaries[0])
    timed = timing_runs(summaries)
    tc = sorted(figures(s)["t_contact_us"] for s in timed)
    ts = sorted(figures(s)["t_step_us"] for s in timed)
    f["t_contact_us"] = rules.median(tc)
    f["t_contact_range"] = "%.3g-%.3g" % (tc[0], tc[-1])
    f["t_contact_min_us"], f["t_contact_max_us"] = tc[0], tc[-1]
    f["t_step_us"] = rules.median(ts)
    f["t_step_min_us"], f["t_step_max_us"] = ts[0], ts[-1]
    f.update(pooled(timed))
    f["repeats"] = len(timed)
    return f


def refine_sets(scene, r, doc=None):
    """The --set overrides that make the scene's meshes r times finer (r a power of two); `doc`:
    the scene's document (default: the bundled file's)."""
    s = doc or reader.bundled_scene(scene)
    sets = []
    for i, b in enumerate(s["bodies"]):
        sh = b["shape"]
        if sh["type"] == "box":
            sets.append("bodies.%d.shape.cells=%s" % (i, json.dumps([c * r for c in sh["cells"]])))
        elif sh["type"] in ("sphere", "ellipsoid"):
            sets.append("bodies.%d.shape.subdivisions=%d" % (i, sh.get("subdivisions", 2) + int(math.log2(r))))
        elif sh["type"] == "cylinder":
            sets.append("bodies.%d.shape.segments=%d" % (i, sh.get("segments", 16) * r))
            sets.append("bodies.%d.shape.rings=%d" % (i, sh.get("rings", 4) * r))
    return sets


def read_rows(a, name):
    """A study's CSV in --results (reader.read_csv: numbers as floats, NaN when empty)."""
    return reader.read_csv(os.path.join(a.results, name), text=reader.STUDY_TEXT)


def table_path(a, name):
    return os.path.join(a.results, "tables", name)


def figure_path(a, name):
    return os.path.join(a.results, "figures", name)
