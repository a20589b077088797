"""study.py realtime: real time as a reviewer would accept it.

Per scene and method: the collision unit's time per step (detection + response) and the whole
simulator's (real-time factor = simulated time per wall time = dt / step time), on the mean and the
99th percentile of the steps, against the budget of one step, the scene's dt (the 1 ms haptic line
beside), in three modes: at the scene's dt; at 0.9 of the smallest dt_crit the run at the scene's
dt met (the guard `substep` as a safety net: its substeps are inside the step's time); and with
implicit Euler at ten times the scene's dt. One and two threads (HARNESS_THREADS). Each row carries
its error against the reference over the final window, from one untimed run (one thread, settled,
measured; the two-thread run steps the same state bit for bit: its error is the one-thread run's),
the ratio of that error to the best exact method's at the scene's dt, its timings from --repeats
timed runs per thread count that each do the same work, one at a time (run()), the machine as the
runs recorded it, and the arguments after `harness run SCENE` that reproduce it. Timings exclude
the references' measurement (no timed run measures). -> realtime.csv, tables/realtime.{md,tex}.
Cached like every study run.
"""
import json
import math
import os
import shlex

from .. import reader, rules, runner, writers
from .common import (PENALTY, STUDY_EVERY, figures, mark_useless, pooled, reference_dir, scene_arg, scene_doc,
                     scenes, table_path)
from .common import columns_of

HAPTIC_BUDGET_US = 1000.0
# (label, kind, --set overrides): kind "exact" (an exact detector), "completed" (voxel_exact), "paper".
REALTIME_METHODS = [
    ("cgal both ways, penalty (scene default)", "exact", []),
    ("voxel_exact both ways, penalty", "completed", ['contacts.0.detector="voxel_exact"']),
    ("voxel, scene size, line, auto (the paper's)", "paper",
     ['contacts.0.detector="voxel"', 'contacts.0.eliminator="line"', 'contacts.0.force="auto"',
      "contacts.0.two_sided=false"]),
]


def realtime_methods(a, scene):
    """REALTIME_METHODS; on a user's scene (whose own contact may be anything) the exact and the
    completed methods are set in full: both ways, the scene's penalty (or k = 500 N/m)."""
    if not getattr(a, "user", None):
        return REALTIME_METHODS
    force = (scene_doc(a, scene).get("contacts") or [{}])[0].get("force")
    penalty = json.dumps(force) if isinstance(force, dict) else PENALTY
    both = ["contacts.0.two_sided=true", "contacts.0.force=" + penalty]
    return [("cgal both ways, penalty", "exact", ['contacts.0.detector="cgal"'] + both),
            ("voxel_exact both ways, penalty", "completed", ['contacts.0.detector="voxel_exact"'] + both),
            REALTIME_METHODS[2]]


def shell_args(args):
    """The arguments as one shell-quoted string."""
    return " ".join(shlex.quote(x) for x in args)


def realtime_run(a, scene, folder, args, threads, compare):
    """`harness run SCENE ARGS` with `threads` threads (its summary), measured against the reference
    by CGAL every STUDY_EVERY steps when compare, without references otherwise."""
    out = os.path.join(a.results, "sweeps", "realtime", folder)
    cmd = ["run", scene_arg(a, scene), "--out", out, "--quiet", "--set", "output.frames_every=0"] + args
    ref = reference_dir(a, scene)
    if compare and os.path.exists(os.path.join(ref, "surfaces.csv")):
        cmd += ["--set", 'references.solvers=["cgal"]', "--set", "references.every=%d" % STUDY_EVERY, "--compare", ref]
    else:
        cmd += ["--set", "references.solvers=[]"]
    if a.quick:
        cmd += ["--set", "time.steps=300", "--set", "time.settle.max_steps=400"]
    return runner.harness(a, cmd, out, threads=str(threads))


def modes(a, scene, base, first):
    """(mode, arguments) of one method: the scene's dt, 0.9 of the smallest dt_crit the run at the
    scene's dt met (when it reported one), implicit Euler at ten times the scene's dt."""
    dt0 = scene_doc(a, scene)["time"]["dt"]
    dt_crit_min = reader.stepping(first)["dt_crit_min"]
    out = [("scene dt", base)]
    if dt_crit_min > 0:
        out.append(("0.9 dt_crit", base + ["--dt", "%.4g" % (0.9 * dt_crit_min), "--set", 'time.guard="substep"']))
    out.append(("implicit Euler, 10 dt", base + ["--dt", "%.4g" % (10 * dt0), "--set", 'time.integrator="implicit_euler"']))
    return out


def timing_of(runs):
    """The timing columns of a row from its timed repeats (each the same work: the scene's steps,
    no settling, no references): per step the median (of the repeats' medians), the mean (of their
    means: equal step counts, so the pooled mean), the p99 (median of the repeats' p99s) and the
    maximum (over all); the collision unit's median, mean and p99 likewise; the repeats' range of
    means; the real-time factors on the mean and the p99; the machine and threads as the runs
    recorded them."""
    d = [reader.step_distribution(s) for s in runs]
    out = pooled(runs)
    med = rules.median([reader.step_time_us(s) for s in runs])
    mean, p99 = out["t_step_mean_us"], out["t_step_p99_us"]
    budget = d[0]["budget_us"] if d else float("nan")
    means = [x["step_mean_us"] for x in d]
    out.update({"t_step_us": med, "t_step_max_us": max((x["step_max_us"] for x in d), default=float("nan")),
                "t_step_mean_range": "%.4g-%.4g" % (min(means), max(means)) if means else "",
                "t_contact_us": rules.median([reader.contact_time_us(s) for s in runs]), "budget_us": budget,
                "realtime_factor": budget / med if med > 0 else float("nan"),
                "realtime_factor_mean": budget / mean if mean > 0 else float("nan"),
                "realtime_factor_p99": budget / p99 if p99 > 0 else float("nan"),
                "repeats": len(runs), "threads_recorded": d[0]["threads"] if d else "",
                "timed_steps": reader.steps_run_or_none(runs[0]) if runs else ""})
    return out


def row_of(scene, label, kind, mode, threads, args, s, timed):
    """A row: the error run `s` (one thread, settled, measured against the reference) and the
    timed repeats `timed` of the same configuration at `threads` threads."""
    st = reader.stepping(s)
    f = figures(s)
    r = {"scene": scene, "method": label, "kind": kind, "mode": mode, "threads": threads, "dt": st["dt"],
         "integrator": st["integrator"], "substeps_max": st["max_substeps"], "overrides": shell_args(args),
         "pos_err_max_mm": f["pos_err_max_mm"], "tunnelled": f["tunnelled"], "stability": f["stability"],
         "status": reader.status(s), "steps": reader.steps_run_or_none(s), "forced": f["forced"]}
    r.update(timing_of(timed))
    r["contact_budget_share"] = r["t_contact_mean_us"] / r["budget_us"] if r["budget_us"] > 0 else float("nan")
    r["contact_haptic_share"] = r["t_contact_mean_us"] / HAPTIC_BUDGET_US
    return r


def timed_run(a, scene, folder, args, threads):
    """One timed repeat: the scene's time.steps (at the mode's dt), no settling, no references, no
    frames; `threads` threads."""
    return realtime_run(a, scene, folder, args + ["--set", "time.settle=null"], threads, False)


def run(a):
    """The protocol (what a referee accepts): the error of each configuration comes from one run on
    one thread, settled and measured against the reference, which is not timed; its timings come
    from --repeats runs at one thread and --repeats at two, every one doing the same work (the
    scene's steps at the mode's dt, without settling or references), executed one at a time on the
    otherwise idle machine whatever -j says."""
    rows = []
    plan = []
    for scene in scenes(a):
        for label, kind, sets in realtime_methods(a, scene):
            tag = label.split(" (")[0].replace(" ", "_").replace(",", "")
            plan.append((scene, label, kind, runner.sets_args(sets), tag))
    # The error runs (untimed: -j at once): the scene's dt first (its smallest dt_crit sets the
    # dt of the second mode), then the other modes.
    firsts = runner.parallel(a, lambda p: realtime_run(a, p[0], "%s/%s_scene_dt_t1" % (p[0], p[4]), p[3], 1, True), plan)
    configs = []
    for (scene, label, kind, base, tag), first in zip(plan, firsts):
        for mode, args in modes(a, scene, base, first):
            stem = "%s/%s_%s" % (scene, tag, mode.split(",")[0].replace(" ", "_").replace(".", ""))
            configs.append((scene, label, kind, mode, args, stem, first if mode == "scene dt" else None))
    todo = [c for c in configs if c[6] is None]
    errs = dict(zip([c[5] for c in todo],
                    runner.parallel(a, lambda c: realtime_run(a, c[0], c[5] + "_t1", c[4], 1, True), todo)))
    # The timed repeats, one at a time, alternating the configurations so that a slow spell of the
    # machine falls on all of them alike.
    timed = {}
    for r in range(a.repeats):
        for (scene, label, kind, mode, args, stem, first) in configs:
            for threads in [1, 2]:
                timed.setdefault((stem, threads), []).append(
                    timed_run(a, scene, "%s_timed_t%d_r%d" % (stem, threads, r), args, threads))
    for scene in scenes(a):
        srows = []
        for (sc, label, kind, mode, args, stem, first) in configs:
            if sc != scene:
                continue
            err = first if first is not None else errs[stem]
            for threads in [1, 2]:
                runs = [t for t in timed[(stem, threads)] if reader.status(t) == "ok"]
                srows.append(row_of(scene, label, kind, mode, threads, args, err, runs or [err]))
        # The best exact method's error at the scene's dt: every row's error against it.
        exact = [r["pos_err_max_mm"] for r in srows if r["kind"] == "exact" and r["mode"] == "scene dt"
                 and r["threads"] == 1 and not math.isnan(r["pos_err_max_mm"])]
        best = min(exact) if exact else float("nan")
        for r in srows:
            r["best_exact_mm"] = best
            r["error_over_best"] = r["pos_err_max_mm"] / best if best > 0 else float("nan")
        rows += srows
    for r in rows:
        r["device"] = "cpu"
    write_outputs(a, rows + device_rows(a, rows))


# The device rows: `harness run SCENE --device cuda` summaries kept in results/device/runs/ (made by
# scripts/device_check.sh on a GPU machine, which CI and this study cannot run).
DEVICE_METHOD = ("voxel_exact both ways, penalty", "completed", "voxel_exact_full")


def device_rows(a, cpu_rows):
    """One row per scene with a device run: the completed model at the scene's dt on the GPU over the
    scene's time.steps (no settling: not on a device), every step waited for (mean, median, p99,
    max). A device measures no error (no references there): the row's error, stability and
    tunnelling are empty, and the CPU twin's (same method, scene dt, one thread, measured over its
    settled run's final window) stand beside them as cpu_twin_*; the GPU's states agree with the
    CPU's over the steps both ran (results/device/state_check.csv), not beyond."""
    label, kind, stem = DEVICE_METHOD
    out = []
    for scene in scenes(a):
        path = os.path.join(a.results, "device", "runs", "%s_%s" % (scene, stem), "summary.json")
        if not os.path.isfile(path):
            continue
        s = reader.load_summary(path)
        t = reader.device_timing(s)
        twin = next((r for r in cpu_rows if r["scene"] == scene and r["method"] == label and r["mode"] == "scene dt"
                     and int(r["threads"]) == 1), {})
        dt = t["dt"]
        med = t["median_us"]
        out.append({"scene": scene, "method": label, "kind": kind, "mode": "scene dt", "threads": 1, "dt": dt,
                    "integrator": "symplectic_euler", "substeps_max": 1, "t_step_us": med,
                    "t_step_mean_us": t["mean_us"], "t_step_p99_us": t["p99_us"], "t_step_max_us": t["max_us"],
                    "budget_us": t["budget_us"], "t_contact_us": float("nan"), "contact_budget_share": float("nan"),
                    "realtime_factor": dt * 1e6 / med if med > 0 else float("nan"),
                    "realtime_factor_mean": t["realtime_factor_mean"], "realtime_factor_p99": t["realtime_factor_p99"],
                    "pos_err_max_mm": float("nan"), "tunnelled": "", "error_over_best": float("nan"), "stability": "",
                    "best_exact_mm": twin.get("best_exact_mm", float("nan")),
                    "cpu_twin_pos_err_max_mm": twin.get("pos_err_max_mm", float("nan")),
                    "cpu_twin_error_over_best": twin.get("error_over_best", float("nan")),
                    "cpu_twin_stability": twin.get("stability", ""), "cpu_twin_steps": twin.get("steps", ""),
                    "status": reader.status(s), "steps": reader.steps_run_or_none(s),
                    "overrides": "--device cuda --steps %s --set 'contacts.0.detector=\"voxel_exact\"' --set "
                                 "'references.solvers=[]'" % reader.steps_requested(s),
                    "device": t["device"], "machine": "%s (%s cores)" % (t["machine_cpu"], t["machine_cores"])})
    return out


def plots(a):
    """--plots-only: realtime.csv's CPU rows as they are, the device rows made again from
    results/device/runs/, and the tables; runs nothing."""
    rows = reader.read_csv(os.path.join(a.results, "realtime.csv"), text=TEXT, missing=[])
    cpu = [r for r in rows if r.get("device") in (None, "", "cpu")]
    for r in cpu:  # the device rows' columns, empty on the CPU's
        for k in ("cpu_twin_pos_err_max_mm", "cpu_twin_error_over_best", "cpu_twin_stability", "cpu_twin_steps"):
            r[k] = ""
    for r in cpu:
        r["device"] = "cpu"
    write_outputs(a, cpu + device_rows(a, cpu))


COLS = ["scene", "method", "kind", "mode", "threads", "dt", "integrator", "substeps_max", "t_step_us", "t_contact_us",
        "contact_budget_share", "realtime_factor", "pos_err_max_mm", "tunnelled", "best_exact_mm", "error_over_best",
        "stability", "useless", "status", "steps", "overrides", "device", "t_step_mean_us", "t_step_p99_us", "t_step_max_us",
        "budget_us", "realtime_factor_mean", "realtime_factor_p99", "machine", "cpu_twin_pos_err_max_mm",
        "cpu_twin_error_over_best", "cpu_twin_stability", "cpu_twin_steps", "t_step_mean_range", "t_contact_mean_us",
        "t_contact_p99_us", "contact_haptic_share", "repeats", "threads_recorded", "timed_steps"]
TEXT = ("scene", "method", "kind", "mode", "integrator", "stability", "status", "overrides", "device", "machine",
        "tunnelled", "t_step_mean_range")


def write_outputs(a, rows):
    """realtime.csv, tables/realtime.md and tables/realtime.tex; each row marked useless (tunnels, or
    no better than no force: common.mark_useless against the accuracy study's runs without force)."""
    cols = COLS
    mark_useless(a, rows)
    writers.write_csv(os.path.join(a.results, "realtime.csv"), rows, columns_of(cols, rows))
    heads = ["scene", "method", "kind", "mode", "threads", "dt (s)", "integrator", "substeps (error run's max)",
             "step median (µs)",
             "detect+response median (µs)", "detect+response mean / dt", "RTF (median)", "pos. error (mm)", "tunnelled",
             "best exact (mm)", "error / best", "stability", "useless", "status", "error run's steps", "arguments after "
             "`harness run SCENE`", "device", "step mean (µs)", "step p99 (µs)", "step max (µs)", "budget = the run's dt (µs)",
             "RTF mean", "RTF p99", "machine", "CPU twin's error (mm)", "CPU twin's error / best", "CPU twin's stability",
             "CPU twin's steps", "repeats' step means (µs)", "detect+response mean (µs)", "detect+response p99 (µs)",
             "detect+response mean / 1 ms", "repeats", "threads recorded", "timed steps"]
    with open(table_path(a, "realtime.md"), "w") as f:
        f.write("# Real time\n\nPer scene and method: the whole step's time (the simulator's: real-time factor RTF = "
                "simulated time per wall time = dt / step time, on the mean and on the 99th percentile of the steps) "
                "and the collision unit's (detection + response), against the real-time budget of one step, the "
                "run's dt (the scene's dt in mode scene dt; the 1 ms haptic line beside), at the scene's dt, at 0.9 of the smallest dt_crit the "
                "run at the scene's dt met (guard `substep` as a safety net: its substeps are inside the step's "
                "time), and with implicit Euler at ten times the scene's dt; one and two threads (HARNESS_THREADS). "
                "The protocol: the error comes from one run on one thread, settled and measured against the "
                "reference over its final window, and is not timed (the two-thread run steps the same state bit for "
                "bit: its error is the one-thread run's); the timings come from `repeats` runs per thread count, "
                "every one the same work (the scene's steps at the mode's dt, no settling, no references), executed "
                "one at a time; per step the median (of the repeats' medians), mean (pooled), p99 (median of the "
                "repeats') and maximum; `machine` and `threads recorded` as the runs read them from the system. The "
                "error's ratio to the best exact method's at the scene's dt beside; useless beside the stability: "
                "tunnels, or no better than no force. `arguments`: what follows `harness run SCENE` to reproduce "
                "the row. Made by `scripts/study.py realtime`; the machine is shared: timings vary. Rows whose "
                "`device` is not cpu: the completed model on a GPU (`harness run SCENE --device cuda`, "
                "scripts/device_check.sh), over the scene's time.steps (no settling) with every step waited for, on "
                "another machine (its `machine`). A device measures no error: theirs is empty, and the CPU twin's "
                "(same method, scene dt, one thread, over its settled run) stands beside it; the GPU's states agree "
                "with the CPU's over the steps both ran (results/device/state_check.csv).\n\n"
                + writers.md_table(rows, cols, heads))
    with open(table_path(a, "realtime.tex"), "w") as f:
        tcols = ["scene", "method", "mode", "device", "threads", "t_step_mean_us", "t_step_p99_us",
                 "t_contact_mean_us", "realtime_factor_mean", "realtime_factor_p99", "error_over_best"]
        f.write(writers.tex_table([dict(r, scene=r["scene"].replace("_", " "),
                                        device="CPU" if r.get("device") == "cpu" else "GPU") for r in rows], tcols,
                                  ["scene", "method", "mode", "on", "threads", "step mean ($\\mu$s)", "step p99 ($\\mu$s)",
                                   "collision mean ($\\mu$s)", "RTF mean", "RTF p99", "error / best exact"], "Real time"))
