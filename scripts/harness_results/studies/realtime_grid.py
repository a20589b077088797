"""study.py realtime_grid: the largest implicit step that keeps the exact method's accuracy, and its
real-time factor.

Per scene, the exact method as the scene writes it (CGAL both ways, the penalty in the implicit
system: core/implicit.hpp) with implicit Euler on a fixed grid of steps, the scene's dt x 2^k for
k = 0..GRID_K (--quick: 0..2; where that would round a driver's steps, the largest step below it that
keeps them whole: points), beside the same method with the scene's explicit integrator at the
scene's dt (the baseline, the best exact method's error) and at 0.9 of the smallest dt_crit the
baseline met (EXPLICIT_CRIT, the guard substepping: the explicit integrator's largest safe step,
judged like the grid's points but never chosen). Each point's error comes from one run on
one thread, settled and measured against the reference over its final window (not timed); its
timings from --repeats runs per thread count (1 and 2), every one the same work (the scene's
time.steps at that dt, no settling, no references), one at a time, alternating the points. A point
keeps the accuracy when it finished, ran the scene's loading (no driver's steps rounded by --dt,
which would change its travel: moved_driver; every rounded count of the forcing is in column rounded,
from the run's warnings), let no
node through, is not of an unstable class (the judge's UNSTABLE) nor stopped before its forcing
ended, and its largest error over its final window is at most WITHIN times the baseline's (a point
still drifting is judged by where it got to, not by its window mean); the chosen step is the largest
grid step that keeps it (column chosen). The front over the integrator and the step (column front, and
figures/realtime_grid.pdf): per scene, the points that no other point beats on both the error and
the wall time per simulated second (one thread), beyond the noise (rules.pareto: 10 % and the
reference's floor on the error, the window's maximum as the points are judged; the repeats' ranges
on the time), among those that finished, let
nothing through and are not unstable: what each millisecond buys. -> realtime_grid.csv,
tables/realtime_grid.md, figures/realtime_grid.pdf; --plots-only writes the last two and the front
again from the CSV. Cached like every study run (results/sweeps/realtime/<scene>/grid_*).
"""
import math
import os
import re

from .. import reader, rules, style, writers
from ..judge.measure import UNSTABLE
from .common import figure_path, figures, reference_floor_mm, scene_doc, scenes, table_path
from .realtime import realtime_run, timed_run, timing_of

GRID_K = 7          # steps up to 128 times the scene's dt
WITHIN = 1.5        # the accuracy kept: error at most 1.5 times the explicit baseline's
METHOD = "cgal both ways, penalty (scene default)"


def grid(a):
    """The exponents k of the grid (dt x 2^k)."""
    return list(range(3 if a.quick else GRID_K + 1))


EXPLICIT_CRIT = "explicit 0.9 dt_crit"  # the explicit integrator at its largest safe step, beside the grid
CRIT_SHARE = 0.9


def forcing_counts(doc):
    """The step counts of a scene document's forcing, as --dt scales them: each driver's to_step and
    from_step - 1 (a first step: step k starts after k - 1), each load's and pressure's ramp_steps;
    the positive ones."""
    out = []
    for b in (doc or {}).get("bodies", []):
        for d in b.get("drivers") or []:
            out += [int(d.get("to_step", -1)), int(d.get("from_step", 0)) - 1]
        for l in b.get("loads") or []:
            out.append(int(l.get("ramp_steps", 0)))
        p = b.get("pressure")
        if isinstance(p, dict):
            out.append(int(p.get("ramp_steps", 0)))
    return [n for n in out if n > 0]


def driver_counts(doc):
    """The step counts of a scene document's drivers alone (each to_step and from_step - 1): the counts
    whose rounding changes a driver's travel (moved_driver)."""
    out = []
    for b in (doc or {}).get("bodies", []):
        for d in b.get("drivers") or []:
            out += [int(d.get("to_step", -1)), int(d.get("from_step", 0)) - 1]
    return [n for n in out if n > 0]


def whole_dt(dt0, dt, counts):
    """The largest step at or below `dt` at which every count in `counts` (steps at the scene's `dt0`)
    stays a whole number of steps: dt0 G / m, G their greatest common divisor, m the least whole
    number that brings it to dt or below; `dt` itself without counts."""
    G = 0
    for n in counts:
        G = math.gcd(G, int(n))
    return dt0 * G / math.ceil(G * dt0 / dt - 1e-9) if G else dt


def crit_point(dt_crit_min, dt0=None, counts=()):
    """The explicit point near CRIT_SHARE of the smallest dt_crit the baseline met (the guard substeps
    where a step would pass it), as realtime.csv's mode "0.9 dt_crit": the largest dt at or below it
    at which every count of the scene's forcing (`counts` at the scene's `dt0`, forcing_counts) stays
    a whole number of steps, so that the drivers travel as written (dt = dt0 G / m, G their greatest
    common divisor); CRIT_SHARE dt_crit itself without counts. None when the baseline reported no
    dt_crit."""
    if not dt_crit_min > 0:
        return None
    dt = CRIT_SHARE * dt_crit_min
    if dt0 and counts:
        dt = whole_dt(dt0, dt, counts)
    return (EXPLICIT_CRIT, "", dt, "symplectic_euler", ["--dt", "%.17g" % dt, "--set", 'time.guard="substep"'])


def on_grid(r):
    """A point of the implicit grid (k0, k1, ...), not the baseline nor the explicit 0.9 dt_crit."""
    return re.fullmatch(r"k\d+", str(r.get("point", ""))) is not None


def points(a, scene):
    """(label, k, dt, integrator, arguments after `harness run SCENE`) of a scene: the explicit
    baseline, then the implicit grid (the explicit point at 0.9 dt_crit follows the baseline's run:
    crit_point). Point k's step is the scene's dt x 2^k, or where that would round a driver's steps
    (its travel would change: moved_driver) the largest step below it that keeps them whole
    (whole_dt: the spheres at 64x dt run 3.158 ms, not 3.2 ms)."""
    doc = scene_doc(a, scene)
    dt0 = doc["time"]["dt"]
    out = [("baseline", 0, dt0, "symplectic_euler", [])]
    for k in grid(a):
        dt = whole_dt(dt0, dt0 * 2 ** k, driver_counts(doc))
        out.append(("k%d" % k, k, dt, "implicit_euler",
                    ["--dt", "%.17g" % dt if dt != dt0 * 2 ** k else "%.6g" % dt, "--set",
                     'time.integrator="implicit_euler"']))
    return out


def implicit_stats(s):
    """The conjugate gradient's figures of a run (summary stability.implicit; NaN without)."""
    imp = (s.get("stability") or {}).get("implicit") or {}
    return {"cg_tolerance": reader.num(imp.get("cg_tolerance")),
            "cg_mean_iterations": reader.num(imp.get("cg_mean_iterations")),
            "cg_max_iterations": reader.num(imp.get("cg_max_iterations")),
            "cg_unconverged_solves": reader.num(imp.get("cg_unconverged_solves"))}


def window_max(r):
    """A row's largest error over its final window (pos_err_max_max_mm), its mean where the row has
    no maximum."""
    m = reader.num(r.get("pos_err_max_max_mm"))
    return m if m == m else reader.num(r.get("pos_err_max_mm"))


def keeps(r, best):
    """Why a point does not keep the accuracy ("" when it does): `best` is the baseline's largest error
    over its window, and the point's must stay within WITHIN times it over the whole of its own
    window (a point still drifting is judged by where it got to, not by its mean)."""
    if r["status"] != "ok":
        return "status " + str(r["status"])
    if moved_driver(r):
        return "not the scene: a driver's steps rounded by --dt (its travel changes): " + str(r["rounded"])
    if reader.num(r.get("tunnelled")) > 0:
        return "tunnelled"
    if r.get("stability_class") in UNSTABLE:
        return r["stability_class"]
    if r.get("stability_class") == "forced":
        return "not judged: stopped before its forcing ended"
    err = window_max(r)
    if not err == err:
        return "no error measured"
    if not err <= WITHIN * best:
        return "error (window max) %.3g mm > %.3g x %.3g mm" % (err, WITHIN, best)
    return ""


def moved_driver(r):
    """Whether --dt rounded a driver's steps for the point (column rounded): a driver moving at its
    velocity over a rounded number of steps travels another distance, so the point settles into
    another state than the scene's (the spheres at 64x: 38 steps for 37.5, 0.08 mm further). A
    rounded load or pressure ramp reaches the same load, a little sooner or later: kept."""
    return "drivers." in str(r.get("rounded") or "")


def rounded_counts(s):
    """The step counts `--dt` rounded for a run (its summary's "--dt: ..." warnings: the scene's
    physical times changed, a driver's travel or a ramp's length), joined; "" when none."""
    return "; ".join(w[len("--dt: "):] for w in (s.get("warnings") or []) if str(w).startswith("--dt: "))


def run(a):
    """The error runs (-j at once), then the timed repeats one at a time, then the rows."""
    from .. import runner
    plan = [(scene,) + p for scene in scenes(a) for p in points(a, scene)]
    stem = lambda p: "%s/grid_%s" % (p[0], p[1].replace(" ", "_").replace(".", ""))  # noqa: E731
    errs = runner.parallel(a, lambda p: realtime_run(a, p[0], stem(p) + "_t1", p[5], 1, True), plan)
    # The explicit point at 0.9 dt_crit: its dt comes from the baseline's run, so its error run follows.
    crit = [(p[0],) + c for p, s in zip(plan, errs) if p[1] == "baseline"
            for c in [crit_point(reader.stepping(s)["dt_crit_min"], scene_doc(a, p[0])["time"]["dt"],
                                 forcing_counts(scene_doc(a, p[0])))] if c]
    plan += crit
    errs += runner.parallel(a, lambda p: realtime_run(a, p[0], stem(p) + "_t1", p[5], 1, True), crit)
    timed = {}
    for r in range(a.repeats):
        for p in plan:
            for threads in (1, 2):
                timed.setdefault((stem(p), threads), []).append(
                    timed_run(a, p[0], "%s_timed_t%d_r%d" % (stem(p), threads, r), p[5], threads))
    rows = []
    for scene in scenes(a):
        srows = []
        for p, s in zip(plan, errs):
            if p[0] != scene:
                continue
            f = figures(s)
            r = {"scene": scene, "method": METHOD, "point": p[1], "k": p[2] if on_grid({"point": p[1]}) else "",
                 "dt": p[3], "integrator": p[4], "status": reader.status(s), "steps": reader.steps_run_or_none(s),
                 "pos_err_max_mm": f["pos_err_max_mm"], "pos_err_max_max_mm": f.get("pos_err_max_max_mm"),
                 "pos_err_amp_mm": f.get("pos_err_amp_mm"), "settled": f.get("settled", ""),
                 "tunnelled": f["tunnelled"], "rounded": rounded_counts(s),
                 "stability_class": f.get("stability_class", ""), "overrides": " ".join(p[5])}
            r.update(implicit_stats(s))
            for threads in (1, 2):
                runs = [t for t in timed[(stem(p), threads)] if reader.status(t) == "ok"]
                t = timing_of(runs) if runs else {}
                for key in ("t_step_mean_us", "t_step_p99_us", "realtime_factor_mean", "realtime_factor_p99",
                            "t_step_mean_range"):
                    r["%s_t%d" % (key, threads)] = t.get(key, float("nan") if key != "t_step_mean_range" else "")
                r["repeats"] = len(runs)
                r["machine"] = t.get("machine", "")
            srows.append(r)
        decide(srows)
        rows += srows
    write_outputs(a, rows)


def wall_range(r):
    """(low, high) of the repeats' mean step times at one thread (t_step_mean_range_t1, "lo-hi"), µs;
    the mean itself twice where the range is not recorded."""
    m = re.match(r"^\s*([0-9.]+(?:e[+-]?[0-9]+)?)-([0-9.]+(?:e[+-]?[0-9]+)?)\s*$", str(r.get("t_step_mean_range_t1") or ""))
    t = reader.num(r.get("t_step_mean_us_t1"))
    return (float(m.group(1)), float(m.group(2))) if m else (t, t)


def evidence(r):
    """A point the front may rest on: it finished, let nothing through and is neither unstable nor
    stopped before its forcing ended."""
    return (r.get("status") == "ok" and reader.num(r.get("tunnelled"), 0.0) == 0 and not moved_driver(r)
            and r.get("stability_class") not in UNSTABLE + ("forced", "failed"))


def mark_front(srows, floor_mm):
    """A scene's rows given wall_per_sim_s (wall seconds per simulated second at one thread: 1 / the
    real-time factor on the mean) and front ("yes" on the front of error against it, module
    docstring); returns the front. The error is the window's maximum, as the points are judged (a
    point's swing is in it, so it does not widen the noise: a noisier point is not rewarded)."""
    shadow = []
    for r in srows:
        dt = reader.num(r.get("dt"))
        t = reader.num(r.get("t_step_mean_us_t1"))
        lo, hi = wall_range(r)
        r["wall_per_sim_s"] = t * 1e-6 / dt if dt > 0 else float("nan")
        shadow.append({"row": r, "pos_err_max_mm": window_max(r), "pos_err_amp_mm": 0.0,
                       "stable": "yes" if evidence(r) else "no",
                       "tunnelled": 0, "helps": "", "wall_us": r["wall_per_sim_s"],
                       "wall_min_us": lo * 1e-6 / dt if dt > 0 else float("nan"),
                       "wall_max_us": hi * 1e-6 / dt if dt > 0 else float("nan")})
    shadow = [x for x in shadow if not (math.isnan(x["pos_err_max_mm"]) or math.isnan(x["wall_us"]))]
    front = [x["row"] for x in rules.pareto(shadow, floor=floor_mm, x="wall")]
    for r in srows:
        r["front"] = "yes" if any(r is f for f in front) else ""
    return front


def decide(srows):
    """A scene's rows judged in place: each point's error over the baseline's (best_exact_mm,
    error_over_best), whether it keeps the accuracy (keeps, why_not; the explicit point at 0.9
    dt_crit too), its step's cost in baseline steps (one thread), and the chosen point: the largest
    implicit grid step that keeps it (none: no row chosen)."""
    base = next(r for r in srows if r["point"] == "baseline")
    best = reader.num(base["pos_err_max_mm"])
    best_max = window_max(base)
    base_t = reader.num(base.get("t_step_mean_us_t1"))
    for r in srows:
        judged = r["point"] != "baseline"
        r["best_exact_mm"] = best
        r["error_over_best"] = reader.num(r["pos_err_max_mm"]) / best if best > 0 else float("nan")
        r["max_over_best"] = window_max(r) / best_max if best_max > 0 else float("nan")
        r["why_not"] = keeps(r, best_max) if judged else ""
        r["keeps"] = ("no" if r["why_not"] else "yes") if judged else ""
        r["cost_in_explicit_steps"] = reader.num(r.get("t_step_mean_us_t1")) / base_t if base_t > 0 else float("nan")
    kept = [r for r in srows if r["keeps"] == "yes" and on_grid(r)]
    chosen = max(kept, key=lambda r: r["dt"]) if kept else None
    for r in srows:
        r["chosen"] = "yes" if r is chosen else ""
    return chosen


COLS = ["scene", "method", "point", "k", "dt", "integrator", "status", "steps", "pos_err_max_mm", "pos_err_max_max_mm",
        "pos_err_amp_mm", "settled", "rounded", "best_exact_mm", "error_over_best", "max_over_best", "tunnelled",
        "stability_class", "keeps", "why_not", "chosen", "cg_tolerance",
        "cg_mean_iterations", "cg_max_iterations", "cg_unconverged_solves", "t_step_mean_us_t1", "t_step_p99_us_t1",
        "realtime_factor_mean_t1", "realtime_factor_p99_t1", "t_step_mean_range_t1", "t_step_mean_us_t2",
        "t_step_p99_us_t2", "realtime_factor_mean_t2", "realtime_factor_p99_t2", "t_step_mean_range_t2",
        "cost_in_explicit_steps", "wall_per_sim_s", "front", "repeats", "machine", "overrides"]
TEXT = ("scene", "method", "point", "k", "integrator", "status", "settled", "rounded", "stability_class", "keeps",
        "why_not", "chosen",
        "t_step_mean_range_t1", "t_step_mean_range_t2", "machine", "overrides", "front")


def plots(a):
    """--plots-only: the front, tables/realtime_grid.md and figures/realtime_grid.pdf again from
    realtime_grid.csv (its rows as they are otherwise); runs nothing."""
    rows = reader.read_csv(os.path.join(a.results, "realtime_grid.csv"), text=TEXT, missing=[])
    if rows:
        write_outputs(a, rows)


def plot_front(a, rows):
    """figures/realtime_grid.pdf: per scene, the error against the wall time per simulated second
    (one thread), the explicit baseline and each implicit step, the front joined."""
    plt = style.pyplot()
    names = [sc for sc in scenes(a) if any(r["scene"] == sc for r in rows)]
    if not names:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(style.TEXT, 2.3), layout="constrained", squeeze=False)
    for ax, scene in zip(axes[0], names):
        sr = [r for r in rows if r["scene"] == scene and not math.isnan(reader.num(r.get("wall_per_sim_s")))]
        for r in sr:
            x, y = reader.num(r["wall_per_sim_s"]), window_max(r)
            implicit = r.get("integrator") == "implicit_euler"
            ok = evidence(r)  # hollow: not evidence
            ax.plot([x], [y], "o" if implicit else "s", color="C0" if implicit else "C3",
                    mfc=None if ok else "none", ms=4, zorder=3)
            ax.annotate(r["point"].replace("baseline", "expl.").replace(EXPLICIT_CRIT, "expl. 0.9 crit"), (x, y),
                        fontsize=5, xytext=(2, 2),
                        textcoords="offset points")
        fr = sorted((r for r in sr if r.get("front") == "yes"), key=lambda r: reader.num(r["wall_per_sim_s"]))
        if fr:
            ax.step([reader.num(r["wall_per_sim_s"]) for r in fr], [window_max(r) for r in fr],
                    where="post", color="k", lw=0.7, zorder=2)
        ax.axvline(1.0, color="0.5", lw=0.6, ls=":")  # real time
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(scene.replace("_", " "), fontsize=7)
        ax.set_xlabel("wall s per simulated s (1 thread)", fontsize=6)
        ax.tick_params(labelsize=5)
    axes[0][0].set_ylabel("pos. error, window max (mm)", fontsize=6)
    style.save(fig, figure_path(a, "realtime_grid"), width=style.TEXT)


def write_outputs(a, rows):
    """The front (mark_front), realtime_grid.csv, tables/realtime_grid.md and figures/realtime_grid.pdf."""
    for scene in sorted({r["scene"] for r in rows}):
        mark_front([r for r in rows if r["scene"] == scene], reference_floor_mm(a, scene))
    writers.write_csv(os.path.join(a.results, "realtime_grid.csv"), rows, COLS)
    plot_front(a, rows)
    short = ["scene", "point", "dt", "integrator", "pos_err_max_mm", "error_over_best", "max_over_best",
             "stability_class", "keeps",
             "why_not", "chosen", "cg_mean_iterations", "t_step_mean_us_t1", "realtime_factor_mean_t1",
             "realtime_factor_p99_t1", "realtime_factor_mean_t2", "realtime_factor_p99_t2", "cost_in_explicit_steps",
             "wall_per_sim_s", "front"]
    heads = ["scene", "point", "dt (s)", "integrator", "pos. error (mm)", "error / baseline", "window max / baseline's",
             "class", "keeps",
             "why not", "chosen", "CG iterations (mean)", "step mean, 1 thread (µs)", "RTF mean, 1 thread",
             "RTF p99, 1 thread", "RTF mean, 2 threads", "RTF p99, 2 threads", "step in baseline steps",
             "wall s per simulated s", "front"]
    repeats = int(max((reader.num(r.get("repeats"), 0) for r in rows), default=0)) or a.repeats
    lines = ["# Real time by the step size", "",
             "The exact method (%s) with implicit Euler at the scene's dt x 2^k (where that would round a driver's "
             "steps, the largest step below it that keeps them whole: column dt), beside the same method with the "
             "explicit integrator at the scene's dt (the baseline) and at 0.9 of the smallest dt_crit the baseline "
             "met (`%s`, the guard substepping). A point keeps the accuracy when it finished, runs the scene's "
             "loading (no driver's steps rounded by --dt, which changes its travel; column rounded), let no node through, is not of an unstable "
             "class (%s) and its largest error over its window is at most %.1f x the baseline's; `chosen` is the largest implicit step that keeps it. RTF = dt / step time, on the mean and the "
             "99th percentile of the steps, from %s timed runs per thread count, one at a time, each the scene's "
             "time.steps at that dt without settling or references; the error from one settled, measured run. "
             "`front`: the points no other beats on both the error and the wall time per simulated second (one "
             "thread) beyond the noise (10 %% and the reference's floor on the error, its window maximum; the repeats' ranges on the "
             "time), among those that finished, let nothing through and are not unstable "
             "(figures/realtime_grid.pdf). "
             "Made by `scripts/study.py realtime_grid`; the machine is shared: timings vary."
             % (METHOD, EXPLICIT_CRIT, ", ".join(UNSTABLE), WITHIN, repeats), ""]
    with open(table_path(a, "realtime_grid.md"), "w") as f:
        f.write("\n".join(lines) + "\n" + writers.md_table(rows, short, heads))
