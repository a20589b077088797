"""study.py realtime: real time as a reviewer would accept it.

Per scene and method: the collision unit's time per step (detection + response, against a 1 ms
haptic budget) and the whole simulator's (real-time factor = simulated time per wall time = dt /
median step), in three modes: at the scene's dt; at 0.9 of the smallest dt_crit the run at the
scene's dt met (the guard `substep` as a safety net: its substeps are inside the step's time); and
with implicit Euler at ten times the scene's dt. One and two threads (HARNESS_THREADS). Each row
carries its error against the reference over the final window (the two-thread run steps the same
state bit for bit: its error is the one-thread run's) and the ratio of that error to the best
exact method's at the scene's dt, and the arguments after `harness run SCENE` that reproduce it.
Timings exclude the references' measurement where the run measured (summary timing_us are the
step's own). -> realtime.csv, tables/realtime.{md,tex}. Cached like every study run.
"""

import json
import math
import os
import shlex

from .. import reader, runner, writers
from .common import (PENALTY, STUDY_EVERY, figures, mark_useless, reference_dir, scene_arg, scene_doc, scenes,
                     table_path)

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


def row_of(scene, label, kind, mode, threads, args, s):
    st = reader.stepping(s)
    dt = st["dt"]
    step_us = reader.step_time_us(s)
    contact_us = reader.contact_time_us(s)
    f = figures(s)
    return {"scene": scene, "method": label, "kind": kind, "mode": mode, "threads": threads, "dt": dt,
            "integrator": st["integrator"], "substeps_max": st["max_substeps"], "overrides": shell_args(args),
            "t_step_us": step_us, "t_contact_us": contact_us, "contact_budget_share": contact_us / HAPTIC_BUDGET_US,
            "realtime_factor": dt * 1e6 / step_us if step_us > 0 else float("nan"),
            "pos_err_max_mm": f["pos_err_max_mm"], "tunnelled": f["tunnelled"], "stability": f["stability"],
            "status": reader.status(s), "steps": reader.steps_run_or_none(s)}


def run(a):
    rows = []
    # One thread, measured against the reference: the scene's dt first (its smallest dt_crit sets
    # the dt of the second mode), then the other modes; -j of them at once (one core each). Then
    # the two-thread runs one at a time (both cores), timing only: the scene's steps without
    # settling and without the references (they step the same state bit for bit as one thread, so
    # their error is the one-thread run's).
    plan = []
    for scene in scenes(a):
        for label, kind, sets in realtime_methods(a, scene):
            tag = label.split(" (")[0].replace(" ", "_").replace(",", "")
            plan.append((scene, label, kind, runner.sets_args(sets), tag))
    firsts = runner.parallel(a, lambda p: realtime_run(a, p[0], "%s/%s_scene_dt_t1" % (p[0], p[4]), p[3], 1, True), plan)
    jobs = []
    for (scene, label, kind, base, tag), first in zip(plan, firsts):
        for mode, args in modes(a, scene, base, first):
            stem = "%s/%s_%s" % (scene, tag, mode.split(",")[0].replace(" ", "_").replace(".", ""))
            for threads in [1, 2]:
                jobs.append((scene, label, kind, mode, threads, args, stem + "_t%d" % threads,
                             first if (mode == "scene dt" and threads == 1) else None))
    one = [j for j in jobs if j[4] == 1 and j[7] is None]
    done = dict(zip([j[6] for j in one], runner.parallel(a, lambda j: realtime_run(a, j[0], j[6], j[5], 1, True), one)))
    for j in jobs:
        if j[4] == 2:
            done[j[6]] = realtime_run(a, j[0], j[6], j[5] + ["--set", "time.settle=null"], 2, False)
    for scene in scenes(a):
        srows = [row_of(scene, label, kind, mode, threads, args, first if first is not None else done[folder])
                 for (sc, label, kind, mode, threads, args, folder, first) in jobs if sc == scene]
        # Two threads step the same state as one (bit-identical): their error is the one-thread run's.
        for r in srows:
            if r["threads"] == 2:
                twin = next(o for o in srows if o["method"] == r["method"] and o["mode"] == r["mode"] and o["threads"] == 1)
                for k in ["pos_err_max_mm", "tunnelled", "stability"]:
                    r[k] = twin[k]
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
    rows = reader.read_csv(os.path.join(a.results, "realtime.csv"),
                           text=("scene", "method", "kind", "mode", "integrator", "stability", "status", "overrides",
                                 "device", "machine", "tunnelled"), missing=[])
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
        "cpu_twin_error_over_best", "cpu_twin_stability", "cpu_twin_steps"]


def write_outputs(a, rows):
    """realtime.csv, tables/realtime.md and tables/realtime.tex; each row marked useless (tunnels, or
    no better than no force: common.mark_useless against the accuracy study's runs without force)."""
    cols = COLS
    mark_useless(a, rows)
    writers.write_csv(os.path.join(a.results, "realtime.csv"), rows, cols)
    heads = ["scene", "method", "kind", "mode", "threads", "dt (s)", "integrator", "substeps", "step (µs)",
             "detect+response (µs)", "of 1 ms", "real-time factor", "pos. error (mm)", "tunnelled", "best exact (mm)",
             "error / best", "stability", "useless", "status", "steps", "arguments after `harness run SCENE`", "device",
             "step mean (µs)", "step p99 (µs)", "step max (µs)", "budget (µs)", "RTF mean", "RTF p99", "machine",
             "CPU twin's error (mm)", "CPU twin's error / best", "CPU twin's stability", "CPU twin's steps"]
    with open(table_path(a, "realtime.md"), "w") as f:
        f.write("# Real time\n\nPer scene and method: the collision unit's time per step (detection + response, "
                "median over the run's steps, against a 1 ms haptic budget) and the whole step's (the simulator's: "
                "real-time factor = simulated time per wall time = dt / median step), at the scene's dt, at 0.9 of "
                "the smallest dt_crit the run at the scene's dt met (guard `substep` as a safety net: its substeps are "
                "inside the step's time), and with implicit Euler at ten times the scene's dt; one and two threads "
                "(HARNESS_THREADS; the two-thread runs time the scene's steps without settling or references); the "
                "error against the reference over the final window beside it (the two-thread run steps the same "
                "state bit for bit: its error is the one-thread run's), and its ratio to the best exact method's at "
                "the scene's dt; useless beside the stability: tunnels, or no better than no force. Timings "
                "exclude the references' measurement. `arguments`: what follows `harness run SCENE` to reproduce "
                "the row. Made by `scripts/study.py realtime`; the machine is shared: timings vary. Rows whose `device` is "
                "not cpu: the completed model on a GPU (`harness run SCENE --device cuda`, scripts/device_check.sh), "
                "over the scene's time.steps (no settling) with every step waited for (mean, median, p99, max), on "
                "another machine than the CPU rows (its `machine`; the CPU rows' machine was not recorded: the "
                "shared two-core machine of the studies). A device measures no error: theirs is empty, and the "
                "CPU twin's (same method, scene dt, one thread, over its settled run) stands beside it; the GPU's "
                "states agree with the CPU's over the steps both ran (results/device/state_check.csv).\n\n"
                + writers.md_table(rows, cols, heads))
    with open(table_path(a, "realtime.tex"), "w") as f:
        tcols = ["scene", "method", "mode", "device", "threads", "t_step_us", "t_contact_us", "realtime_factor",
                 "error_over_best"]
        f.write(writers.tex_table([dict(r, scene=r["scene"].replace("_", " "),
                                        device="CPU" if r.get("device") == "cpu" else "GPU") for r in rows], tcols,
                                  ["scene", "method", "mode", "on", "threads", "step ($\\mu$s)", "collision ($\\mu$s)",
                                   "real-time factor", "error / best exact"], "Real time"))
