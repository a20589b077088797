"""Reading what `harness` and the studies write: the one CSV reader and the one place that knows
summary.json's key paths (core/run/summary.cpp writes them).

CSV files (steps.csv, penetration_episodes.csv, surfaces.csv, the studies' CSV files, bench.csv):
`read_csv` is the only reader. Any of them may be stored gzipped (NAME.csv.gz beside or instead of
NAME.csv: `stored` finds the one there, `open_text` reads either: stored.py); a run's wall times may live in
timing.csv beside steps.csv (keyed by step and pair), which `load_steps` joins back. Its one convention: a column of numbers reads as floats with NaN
where a cell is empty (a written "nan" is NaN too); a column of text (one holding any cell that is
not a number, or one the caller names: STUDY_TEXT for the studies' files) reads as strings, "" where
empty. `present(v)` tells a value from a missing one.

summary.json: `load_summary`, then the accessors below (`pair`, `reference_errors`, `window`,
`window_stat`, `stability_inputs`, `timings`, `contact_time_us`, `window_figures`, `engine`, ...).
A script that needs a figure of a summary asks an accessor; a new key path is added here.
"""

import csv
import json
import math
import os

from .stored import open_text, stored, write_gz  # noqa: F401 (the readers' names for them)

NAN = float("nan")
# The columns of the studies' CSV files (scripts/study.py) that are text whatever their cells hold.
STUDY_TEXT = frozenset([
    "scene", "deformation", "config", "rho_norm", "regime", "response", "detector", "eliminator", "force", "stable", "why_unstable", "settled", "t_contact_range",
    "front", "helps", "useless", "stability", "verdict", "status", "host", "guest", "swapped", "region", "orient", "engine",
    "reference_converged", "resolution", "body", "steps_per_s_range", "reference", "comparison", "converged",
    "reference_rule"])


# ---------------------------------------------------------------------------------------------
# Numbers and CSV files
def num(v, default=NAN):
    """v as a float, `default` when it is not a number (None, "", text)."""
    try:
        return float(v)
    except (TypeError, ValueError):
        return default


def present(v):
    """False for a missing value (None, "", NaN), True otherwise."""
    if v is None or v == "":
        return False
    return not (isinstance(v, float) and math.isnan(v))


def _number(cell):
    """(is a number or empty, value): an empty cell is NaN."""
    if cell is None or cell == "":
        return True, NAN
    try:
        return True, float(cell)
    except ValueError:
        return False, None


def read_csv(path, numbers=(), text=(), missing=None):
    """The rows of a CSV file as dicts (the file's column order), typed by the module's convention.
    `text`: columns read as text whatever they hold; `numbers`: columns that must be there as numbers
    (NaN in every row when the file lacks them). A file that does not exist (nor its .gz form)
    gives `missing`."""
    if stored(path) is None:
        return missing
    with open_text(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return rows
    for k in rows[0].keys():
        if k in text:
            continue
        vals = [_number(r[k]) for r in rows]
        if all(ok for ok, _ in vals):
            for r, (_, v) in zip(rows, vals):
                r[k] = v
    for k in numbers:
        for r in rows:
            r[k] = num(r.get(k))
    return rows


def columns(rows):
    """Rows (dicts) as {column: list of values}."""
    return {k: [r[k] for r in rows] for k in (rows[0].keys() if rows else [])}


# ---------------------------------------------------------------------------------------------
# The outputs of one run folder
TIMING_KEYS = ("step", "pair")


def join_timing(rows, timing):
    """steps.csv's rows with timing.csv's columns added (rows matched on step and pair, in order:
    the harness writes both files row by row); ValueError when the two do not match."""
    if not timing:
        return rows
    if len(timing) != len(rows):
        raise ValueError("timing.csv has %d rows, steps.csv %d" % (len(timing), len(rows)))
    for r, t in zip(rows, timing):
        if any(str(r.get(k)) != str(t.get(k)) for k in TIMING_KEYS):
            raise ValueError("timing.csv row (%s) does not match steps.csv's (%s)"
                             % (",".join(str(t.get(k)) for k in TIMING_KEYS), ",".join(str(r.get(k)) for k in TIMING_KEYS)))
        for k, v in t.items():
            if k not in TIMING_KEYS:
                r[k] = v
    return rows


def load_steps(path):
    """steps.csv of a single-pair run (stored plain or gzipped), with timing.csv's wall times joined
    where it is there, as {column: list} (floats, NaN where not measured)."""
    rows = read_csv(os.path.join(path, "steps.csv"))
    if rows is None:
        raise FileNotFoundError("%s: no steps.csv (nor steps.csv.gz)" % path)
    return columns(join_timing(rows, read_csv(os.path.join(path, "timing.csv"), text=("pair",))))


def load_columns(path, names):
    """Some columns of a run's steps.csv (plain or gzipped) as {column: list of floats, NaN where
    empty}: the fast path for a reader that needs a few of its many columns."""
    f = os.path.join(path, "steps.csv")
    if stored(f) is None:
        raise FileNotFoundError("%s: no steps.csv (nor steps.csv.gz)" % path)
    with open_text(f) as fh:
        rd = csv.reader(fh)
        head = next(rd)
        idx = [head.index(n) for n in names]
        out = {n: [] for n in names}
        for row in rd:
            for n, i in zip(names, idx):
                c = row[i] if i < len(row) else ""
                out[n].append(float(c) if c != "" else NAN)
    return out


def measured(cols, key):
    """(steps, values) of the steps.csv rows where column `key` was measured."""
    st, va = [], []
    for s, v in zip(cols["step"], cols[key]):
        if present(v):
            st.append(int(s))
            va.append(v)
    return st, va


def load_episodes(path):
    """penetration_episodes.csv (node, first_step, last_step, steps, open, tunnelled as ints); [] without
    one. `passages` on each row: whether the file records tunnelled episodes (runs before that
    column: tunnelled 0, passages False)."""
    rows = read_csv(os.path.join(path, "penetration_episodes.csv"), missing=[])
    for r in rows:
        r["passages"] = "tunnelled" in r
        r.setdefault("tunnelled", 0)
        for k in ("node", "first_step", "last_step", "steps", "open", "tunnelled"):
            r[k] = int(r[k])
    return rows


def load_surfaces(path):
    """surfaces.csv of a run: {body: [(x, y, z, x0, y0, z0, signed distance or None)]}."""
    out = {}
    for r in read_csv(os.path.join(path, "surfaces.csv")):
        sd = r["signed_distance"]
        out.setdefault(r["body"], []).append(tuple(r[k] for k in ("x", "y", "z", "x0", "y0", "z0")) +
                                             (sd if present(sd) else None,))
    return out


def largest_displacements(path):
    """{body: largest distance of a surface vertex from its rest position (m)} after the run."""
    return {b: max(math.dist(v[:3], v[3:6]) for v in vs) for b, vs in load_surfaces(path).items()}


# ---------------------------------------------------------------------------------------------
# summary.json: every key path the scripts read is spelled below.
def load_summary(path):
    """summary.json of a run folder (or the file itself)."""
    if os.path.isdir(path):
        path = os.path.join(path, "summary.json")
    with open(path) as f:
        return json.load(f)


def has_summary(path):
    return os.path.exists(os.path.join(path, "summary.json"))


def status(s):
    """"ok", "error" or "interrupted"."""
    return s.get("status")


def steps_run(s):
    return s["steps_run"]


def steps_run_or_none(s):
    """steps_run, None when the summary does not record it."""
    return s.get("steps_run")


def steps_requested(s):
    """The steps a device run was asked for (`harness run --device`), None when not recorded."""
    return s.get("steps_requested")


def scene(s):
    """The scene's name."""
    return s["scene"]


def state_hash(s):
    """The hash of the final state (positions and velocities)."""
    return s["state_hash"]


def cpu_check(s):
    """A device run's check against the CPU (`--check-cpu`): {cpu_state_hash, bit_identical,
    max_node_distance_m}, None when the run made none."""
    c = s.get("cpu_check")
    if not c:
        return None
    return {k: c[k] for k in ("cpu_state_hash", "bit_identical", "max_node_distance_m")}


def stability_verdict(s):
    """The harness's stability verdict of the run's final window (settled, chatters, ...)."""
    return s.get("stability_verdict")


def body_nodes(s, name):
    """Nodes of body `name` (summary `bodies`), None when the summary does not list them."""
    for b in s.get("bodies") or []:
        if b.get("name") == name:
            return int(b["nodes"])
    return None


def nodes(s):
    return s.get("nodes", 0)


def git_commit(s):
    return s["git_commit"]


def scene_file(s):
    """The scene file the run read (None when not recorded)."""
    return s.get("scene_file")


def settled(s):
    """True or False when the scene settles (time.settle), None when it does not."""
    return s["settled"]


def pair(s, i=0):
    """The i-th contact pair's figures ({} when the run has none)."""
    p = s.get("pairs")
    return p[i] if p and len(p) > i else {}


def reference_errors(s, i=0):
    """The pair's error against the reference (--compare): {} without one."""
    return pair(s, i).get("error_vs_reference") or {}


def reference_window(s, i=0):
    """The pair's errors against the reference over the final window ({} without one)."""
    return reference_errors(s, i).get("window") or {}


def pair_window(s, i=0):
    """The pair's own figures over the final window (pairs[].window: depth, penetrating and tunnelled
    nodes, nodes outside the region, ...; {} without one)."""
    return pair(s, i).get("window") or {}


def pair_window_stat(s, name, stat, i=0):
    """One statistic of a pair's window figure, as recorded: from its errors against the reference
    (error_vs_reference.window) where it is one of them, else from the pair's own window; None when
    absent."""
    for w in (reference_window(s, i), pair_window(s, i)):
        if name in w:
            return (w[name] or {}).get(stat)
    return None


def pair_value(s, key, i=0):
    """A pair's figure over the whole run as recorded (None when absent): recall, precision,
    max_depth_final, max_depth_peak, ..."""
    return pair(s, i).get(key)


def voxel_size_used(s, i=0):
    """The voxel size the pair's grid used (m)."""
    return float(pair(s, i)["voxel_size_used"])


def outside_region_peak(s, i=0):
    """The peak of the truly penetrating guest nodes outside the grid's region, NaN when not measured."""
    return num(pair(s, i).get("outside_region_peak"))


def tunnelled_peak(s, i=0):
    """The peak of the nodes that passed through the other body, as recorded (pairs[].tunnelled_peak:
    guest + host where it gives both; else pairs[].tunnelled), None when not measured."""
    p = pair(s, i)
    t = p.get("tunnelled_peak")
    if isinstance(t, dict):
        vals = [v for v in (t.get("guest"), t.get("host")) if v is not None]
        return sum(vals) if vals else None
    return t if t is not None else p.get("tunnelled")


def tunnelled_both(s, i=0):
    """Nodes that passed through the other body at the end, guest and host together (a missing one
    counts 0)."""
    p = pair(s, i)
    return num(p.get("tunnelled"), 0) + num(p.get("tunnelled_host"), 0)


def contacts_last(s, i=0):
    """The pair's contacts at its last step ("" when not recorded)."""
    return pair(s, i).get("contacts_last", "")


def final_reference_errors(s, i=0):
    """pos_err_max, gap_max, depth_max at the end (m), None for a run compared with no reference."""
    e = pair(s, i).get("error_vs_reference")
    if not e:
        return None
    return {k: e[k] for k in ("pos_err_max", "gap_max", "depth_max")}


def window(s):
    """The run's final window and its stability judgement (summary `window`)."""
    return s.get("window") or {}


def window_stat(d, key, what="mean"):
    """A window statistic (mean, max, min, amplitude) of figure `key` in `d` (a `window` object), NaN
    when it was not measured."""
    v = (d or {}).get(key) or {}
    return num(v.get(what)) if isinstance(v, dict) else NAN


def stability_inputs(s):
    """What the studies' stability columns (rules.stability_fields) read from a summary, by name."""
    w = window(s)
    return {"status": s.get("status"), "error": s.get("error"), "finite": s.get("finite"),
            "verdict": s.get("stability_verdict"),
            "rho": num(w.get("contact_power_ratio")),
            "growth": num(w.get("kinetic_growth")),
            "kicked": w.get("kicked"), "net_contact_work": num(w.get("net_contact_work_J")),
            "guard_violations": num((s.get("stability") or {}).get("guard_violations"), 0),
            "balance_error": num((s.get("energy") or {}).get("energy_balance_error"), 0.0)}


def timings(s):
    """Median microseconds per step: step, physics, detect, eliminate, fcl, cgal (None when not timed)."""
    return s.get("timing_us") or {}


def step_time_us(s):
    """The median time of a step, µs (NaN when not timed)."""
    return num(timings(s).get("step"))


def step_distribution(s):
    """A run's per-step wall times beyond the median (summary timing_us, over every step of the run):
    the step's mean, p99 and max and the collision unit's (detection + response) mean and p99, and
    of its two parts apart (detect_*, eliminate_*: runs since those keys), µs;
    the budget (the run's dt, µs: the scene's unless --dt changed it) and the real-time factors on the mean and the p99; the
    machine's processor and cores and the threads the run used, as the run read them from the
    system. NaN / "?" where the run did not record them (runs before these keys)."""
    t = timings(s)
    m = s.get("machine") or {}
    return {"step_mean_us": num(t.get("step_mean")), "step_p99_us": num(t.get("step_p99")),
            "step_max_us": num(t.get("step_max")), "contact_mean_us": num(t.get("contact_mean")),
            "contact_p99_us": num(t.get("contact_p99")), "budget_us": num(s.get("budget_us")),
            "detect_mean_us": num(t.get("detect_mean")), "detect_p99_us": num(t.get("detect_p99")),
            "eliminate_mean_us": num(t.get("eliminate_mean")), "eliminate_p99_us": num(t.get("eliminate_p99")),
            "eliminate_median_us": num(t.get("eliminate")),
            "realtime_factor_mean": num(s.get("realtime_factor_mean")),
            "realtime_factor_p99": num(s.get("realtime_factor_p99")),
            "machine": "%s (%s cores)" % (m.get("cpu", "?"), m.get("cores", "?")), "threads": s.get("threads")}


def stepping(s):
    """How the run stepped (summary `stability`): dt (s) and the smallest dt_crit met (NaN when not
    recorded), integrator, max_substeps (None when not recorded)."""
    st = s.get("stability") or {}
    return {"dt": num(st.get("dt")), "dt_crit_min": num(st.get("dt_crit_min")), "integrator": st.get("integrator"),
            "max_substeps": st.get("max_substeps")}


def device_timing(s):
    """A device run's timing (`harness run --device cuda`, every step waited for): dt (s) and the
    median step (µs) as numbers (NaN when missing); mean, p99 and max step (µs), the budget (µs), the
    real-time factor's mean and p99, the device, and the machine's cpu and cores ("?" when not
    recorded) as recorded."""
    t = timings(s)
    m = s.get("machine") or {}
    return {"dt": num(s.get("dt")), "median_us": num(t.get("median")), "mean_us": t.get("mean"), "p99_us": t.get("p99"),
            "max_us": t.get("max"), "budget_us": s.get("budget_us"), "realtime_factor_mean": s.get("realtime_factor_mean"),
            "realtime_factor_p99": s.get("realtime_factor_p99"), "device": s.get("device"),
            "machine_cpu": m.get("cpu", "?"), "machine_cores": m.get("cores", "?")}


def contact_time_us(s):
    """Detection plus elimination, µs per step (a missing part counts 0)."""
    t = timings(s)
    return num(t.get("detect"), 0.0) + num(t.get("eliminate"), 0.0)


def window_figures(s):
    """The measured figures of one run that the studies use (rules.py's docstring defines window and
    error); lengths in mm. Without its stability judgement (rules.stability_fields)."""
    p = pair(s)
    e = reference_errors(s)
    ew = e.get("window") or {}
    w = window(s)
    t = timings(s)
    mm = lambda v: 1e3 * v
    return {
        "status": status(s), "verdict": s.get("stability_verdict"),
        # rho over the loading period (the harness's rule since it records window.input_period_s) or
        # over the whole time before the window (runs before it)
        "rho_norm": "loading" if "input_period_s" in w else "before window",
        "contact_power_ratio": num(w.get("contact_power_ratio")),
        "settled": s.get("settled"), "steps": s.get("steps_run"), "window_from": w.get("from_step"),
        "pos_err_max_mm": mm(window_stat(ew, "pos_err_max")), "pos_err_max_max_mm": mm(window_stat(ew, "pos_err_max", "max")),
        "pos_err_amp_mm": mm(window_stat(ew, "pos_err_max", "amplitude")), "pos_err_final_mm": mm(num(e.get("pos_err_max"))),
        "pos_err_rms_mm": mm(window_stat(ew, "pos_err_rms")),
        "gap_max_mm": mm(window_stat(ew, "gap_max")), "gap_mean_mm": mm(window_stat(ew, "gap_mean")),
        "depth_max_mm": mm(window_stat(ew, "depth_max", "max")), "depth_peak_mm": mm(num(e.get("depth_peak"))),
        "tunnelled": window_stat(ew, "tunnelled", "max"), "tunnelled_peak": num(e.get("tunnelled_peak")),
        # the nodes through at the end by body (guest through the host, host through the guest): a
        # one-sided method fails on the guest's only (judge/measure.py nodes_through)
        "tunnelled_guest": num(e.get("tunnelled_guest")), "tunnelled_host": num(e.get("tunnelled_host")),
        "t_contact_us": contact_time_us(s), "t_step_us": num(t.get("step")),
        "recall": num(p.get("recall")), "precision": num(p.get("precision")),
        "recall_host": num(p.get("recall_host")), "precision_host": num(p.get("precision_host")),
        "true_pen_final": num(p.get("true_pen_final")), "voxel_size_used": num(p.get("voxel_size_used")),
        "beyond_band_total": num(p.get("beyond_band_total")),
    }


def class_figures(s):
    """The figures the run's C++ stability class was decided on (summary `window`, core/run/window.hpp),
    so that a reader can check it from the row: the chatter's amplitude and its length L (mm) and
    where L came from (voxel, reference floor or edge share), the contact's injection share (against
    contact_input_share), the kinetic energy's growth (against growth_factor) with the window's
    largest kinetic energy and the growth's floor (J: growth counts only when the second half's
    kinetic energy, at most that largest, is above the floor). Empty strings / NaN for runs that
    did not record them (before the class)."""
    w = window(s)
    if "chatter_length_m" not in w:
        return {}
    return {"chatter_amp_mm": 1e3 * num(w.get("chatter_amplitude_m")), "chatter_length_mm": 1e3 * num(w.get("chatter_length_m")),
            "chatter_length_from": w.get("chatter_length_from") or "",
            "injection_share": num(w.get("contact_input_share")), "kinetic_growth": num(w.get("kinetic_growth")),
            "kinetic_max_J": window_stat(w, "kinetic_energy", "max"), "growth_floor_J": num(w.get("growth_floor_J"))}


def pair_figures(s):
    """The pair's figures over the whole run that some studies add: peak depth (mm), region rebuilds."""
    p = pair(s)
    return {"max_depth_peak_mm": 1e3 * num(p.get("max_depth_peak")), "region_rebuilds": num(p.get("region_rebuilds"))}


def end_figures(s):
    """The state at the end of the run: force residual and kinetic energy (NaN when not finite)."""
    return {"residual": num(s.get("residual")), "kinetic_energy_final": num(s.get("kinetic_energy_final"))}


def engine(s):
    """The stepping engine: {"name": "harness"} or Bullet's settings (name, margin_m, ...)."""
    return s.get("engine") or {}


def version(s, what):
    return (s.get("versions") or {}).get(what)


def resolved(s):
    """The resolved scene (every default written in)."""
    return s["resolved_scene"]


def scene_dt(s):
    return float(resolved(s)["time"]["dt"])


def measure_every(s):
    """Steps between two ground-truth measurements (references.every)."""
    return int(resolved(s)["references"]["every"])


def frames_every(s):
    return int(resolved(s).get("output", {}).get("frames_every", 0) or 0)


def contact(s, strict=True):
    """The resolved scene's first contact pair (host, guest, detector, eliminator, force, voxel_size,
    region, margin, ...); strict=False: {} where the summary records none."""
    if not strict:
        return ((s.get("resolved_scene") or {}).get("contacts") or [{}])[0]
    return resolved(s)["contacts"][0]


def scene_bodies(s):
    """The resolved scene's bodies (name, shape, material, constraints)."""
    return resolved(s)["bodies"]


def scene_effects(s):
    """The resolved scene's effects (the names of what acts on it)."""
    return resolved(s)["effects"]


def contact_bodies(s, strict=True):
    """(host, guest) names of the first contact pair; strict=False: None for what the summary does
    not record."""
    c = contact(s, strict)
    return (c["host"], c["guest"]) if strict else (c.get("host"), c.get("guest"))


def reference_levels(s):
    """A `harness reference` summary's levels (dt, stiffness, change_max, ...) and whether it converged."""
    ref = s["reference"]
    return ref["levels"], ref["converged"]


def reference_converged(s):
    return (s.get("reference") or {}).get("converged", "")


# The orders of convergence the loop's Richardson reading is trusted in (first order in dt and
# in 1/k_c is what the reference loop expects).
SANE_ORDER = (0.5, 4.0)


def reference_floor(s):
    """(floor in m, why) of a `harness reference` summary: how far its answer may be from the
    converged one, below which no error measured against it means anything. The last level's
    change when the last order of convergence is sane (SANE_ORDER: the change then bounds the
    remaining error from above); otherwise the largest of the last two changes (the loop is not in
    its asymptotic range: a jump between levels stays possible). NaN when fewer than two levels."""
    ref = s.get("reference") or {}
    if present(ref.get("floor")):  # recorded by harness reference (the same rule)
        return num(ref.get("floor")), ref.get("floor_rule", "")
    levels = ref.get("levels") or []
    changes = [num(lv.get("change_max")) for lv in levels if present(lv.get("change_max"))]
    if not changes:
        return float("nan"), "one level only"
    order = num(levels[-1].get("order"))
    if SANE_ORDER[0] <= order <= SANE_ORDER[1]:
        return changes[-1], "last change (order %.2f)" % order
    return max(changes[-2:]), ("largest of the last two changes (order %.2f: not asymptotic)" % order
                               if present(levels[-1].get("order")) else "largest change (no order yet)")


def reference_floor_mm(results, name):
    """reference_floor of results/references/<name> in mm (NaN when it is missing)."""
    path = os.path.join(results, "references", name)
    if not has_summary(path):
        return float("nan")
    return 1e3 * reference_floor(load_summary(path))[0]


# ---------------------------------------------------------------------------------------------
# Files beside the results
SOURCE = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def bundled_scene(scene):
    """experiments/scenes/<scene>.json, parsed."""
    with open(os.path.join(SOURCE, "experiments", "scenes", scene + ".json")) as f:
        return json.load(f)


def scene_name(scene):
    """The `name` of a scene given as a file or a bundled scene's name."""
    path = scene if os.path.isfile(scene) else os.path.join(SOURCE, "experiments", "scenes", scene + ".json")
    with open(path) as f:
        return json.load(f)["name"]


def read_defaults(results):
    """results/defaults.json (the ablation's defaults per scene, None where none qualifies); {} when missing."""
    path = os.path.join(results, "defaults.json")
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    return {}
