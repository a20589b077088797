"""study.py realtime_grid: the largest implicit step that keeps the exact method's accuracy, and its
real-time factor.

Per scene, the exact method as the scene writes it (CGAL both ways, the penalty in the implicit
system: core/implicit.hpp) with implicit Euler on a fixed grid of steps, the scene's dt x 2^k for
k = 0..GRID_K (--quick: 0..2), beside the same method with the scene's explicit integrator at the
scene's dt (the baseline, the best exact method's error). Each point's error comes from one run on
one thread, settled and measured against the reference over its final window (not timed); its
timings from --repeats runs per thread count (1 and 2), every one the same work (the scene's
time.steps at that dt, no settling, no references), one at a time, alternating the points. A point
keeps the accuracy when it finished, let no node through, is not of an unstable class (the judge's
UNSTABLE) nor stopped before its forcing ended, and its error is at most WITHIN times the baseline's; the chosen step is the largest grid
step that keeps it (column chosen). -> realtime_grid.csv, tables/realtime_grid.md. Cached like
every study run (results/sweeps/realtime/<scene>/grid_*).
"""
import os

from .. import reader, writers
from ..judge.measure import UNSTABLE
from .common import figures, scene_doc, scenes, table_path
from .realtime import realtime_run, timed_run, timing_of

GRID_K = 6          # steps up to 64 times the scene's dt
WITHIN = 1.5        # the accuracy kept: error at most 1.5 times the explicit baseline's
METHOD = "cgal both ways, penalty (scene default)"


def grid(a):
    """The exponents k of the grid (dt x 2^k)."""
    return list(range(3 if a.quick else GRID_K + 1))


def points(a, scene):
    """(label, k, dt, integrator, arguments after `harness run SCENE`) of a scene: the explicit
    baseline, then the implicit grid."""
    dt0 = scene_doc(a, scene)["time"]["dt"]
    out = [("baseline", 0, dt0, "symplectic_euler", [])]
    for k in grid(a):
        dt = dt0 * 2 ** k
        out.append(("k%d" % k, k, dt, "implicit_euler",
                    ["--dt", "%.6g" % dt, "--set", 'time.integrator="implicit_euler"']))
    return out


def implicit_stats(s):
    """The conjugate gradient's figures of a run (summary stability.implicit; NaN without)."""
    imp = (s.get("stability") or {}).get("implicit") or {}
    return {"cg_tolerance": reader.num(imp.get("cg_tolerance")),
            "cg_mean_iterations": reader.num(imp.get("cg_mean_iterations")),
            "cg_max_iterations": reader.num(imp.get("cg_max_iterations")),
            "cg_unconverged_solves": reader.num(imp.get("cg_unconverged_solves"))}


def keeps(r, best):
    """Why a point does not keep the accuracy ("" when it does)."""
    if r["status"] != "ok":
        return "status " + str(r["status"])
    if reader.num(r.get("tunnelled")) > 0:
        return "tunnelled"
    if r.get("stability_class") in UNSTABLE:
        return r["stability_class"]
    if r.get("stability_class") == "forced":
        return "not judged: stopped before its forcing ended"
    err = reader.num(r["pos_err_max_mm"])
    if not err == err:
        return "no error measured"
    if not err <= WITHIN * best:
        return "error %.3g mm > %.3g x %.3g mm" % (err, WITHIN, best)
    return ""


def run(a):
    """The error runs (-j at once), then the timed repeats one at a time, then the rows."""
    from .. import runner
    plan = [(scene,) + p for scene in scenes(a) for p in points(a, scene)]
    stem = lambda p: "%s/grid_%s" % (p[0], p[1])  # noqa: E731
    errs = runner.parallel(a, lambda p: realtime_run(a, p[0], stem(p) + "_t1", p[5], 1, True), plan)
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
            r = {"scene": scene, "method": METHOD, "point": p[1], "k": p[2] if p[1] != "baseline" else "",
                 "dt": p[3], "integrator": p[4], "status": reader.status(s), "steps": reader.steps_run_or_none(s),
                 "pos_err_max_mm": f["pos_err_max_mm"], "tunnelled": f["tunnelled"],
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


def decide(srows):
    """A scene's rows judged in place: each point's error over the baseline's (best_exact_mm,
    error_over_best), whether it keeps the accuracy (keeps, why_not), its step's cost in baseline
    steps (one thread), and the chosen point: the largest step that keeps it (none: no row chosen)."""
    base = next(r for r in srows if r["point"] == "baseline")
    best = reader.num(base["pos_err_max_mm"])
    base_t = reader.num(base.get("t_step_mean_us_t1"))
    for r in srows:
        grid_point = r["point"] != "baseline"
        r["best_exact_mm"] = best
        r["error_over_best"] = reader.num(r["pos_err_max_mm"]) / best if best > 0 else float("nan")
        r["why_not"] = keeps(r, best) if grid_point else ""
        r["keeps"] = ("no" if r["why_not"] else "yes") if grid_point else ""
        r["cost_in_explicit_steps"] = reader.num(r.get("t_step_mean_us_t1")) / base_t if base_t > 0 else float("nan")
    kept = [r for r in srows if r["keeps"] == "yes"]
    chosen = max(kept, key=lambda r: r["dt"]) if kept else None
    for r in srows:
        r["chosen"] = "yes" if r is chosen else ""
    return chosen


COLS = ["scene", "method", "point", "k", "dt", "integrator", "status", "steps", "pos_err_max_mm", "best_exact_mm",
        "error_over_best", "tunnelled", "stability_class", "keeps", "why_not", "chosen", "cg_tolerance",
        "cg_mean_iterations", "cg_max_iterations", "cg_unconverged_solves", "t_step_mean_us_t1", "t_step_p99_us_t1",
        "realtime_factor_mean_t1", "realtime_factor_p99_t1", "t_step_mean_range_t1", "t_step_mean_us_t2",
        "t_step_p99_us_t2", "realtime_factor_mean_t2", "realtime_factor_p99_t2", "t_step_mean_range_t2",
        "cost_in_explicit_steps", "repeats", "machine", "overrides"]


def write_outputs(a, rows):
    """realtime_grid.csv and tables/realtime_grid.md."""
    writers.write_csv(os.path.join(a.results, "realtime_grid.csv"), rows, COLS)
    short = ["scene", "point", "dt", "integrator", "pos_err_max_mm", "error_over_best", "stability_class", "keeps",
             "why_not", "chosen", "cg_mean_iterations", "t_step_mean_us_t1", "realtime_factor_mean_t1",
             "realtime_factor_p99_t1", "realtime_factor_mean_t2", "realtime_factor_p99_t2", "cost_in_explicit_steps"]
    heads = ["scene", "point", "dt (s)", "integrator", "pos. error (mm)", "error / baseline", "class", "keeps",
             "why not", "chosen", "CG iterations (mean)", "step mean, 1 thread (µs)", "RTF mean, 1 thread",
             "RTF p99, 1 thread", "RTF mean, 2 threads", "RTF p99, 2 threads", "step in baseline steps"]
    lines = ["# Real time by the step size", "",
             "The exact method (%s) with implicit Euler at the scene's dt x 2^k, beside the same method with the "
             "explicit integrator at the scene's dt (the baseline). A point keeps the accuracy when it finished, "
             "let no node through, is not of an unstable class (%s) and its error is at most %.1f x the "
             "baseline's; `chosen` is the largest step that keeps it. RTF = dt / step time, on the mean and the "
             "99th percentile of the steps, from %s timed runs per thread count, one at a time, each the scene's "
             "time.steps at that dt without settling or references; the error from one settled, measured run. "
             "Made by `scripts/study.py realtime_grid`; the machine is shared: timings vary."
             % (METHOD, ", ".join(UNSTABLE), WITHIN, a.repeats), ""]
    with open(table_path(a, "realtime_grid.md"), "w") as f:
        f.write("\n".join(lines) + "\n" + writers.md_table(rows, short, heads))
