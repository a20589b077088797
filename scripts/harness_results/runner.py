"""Running the harness for the studies: `harness run` and `harness reference` as child processes
with one thread each (HARNESS_THREADS=1), -j of them at once, a configuration --repeats times.

A run is cached by its summary.json: a folder that has one is not run again (delete the folder, or
results/sweeps/, to rerun). `a` is the parsed command line of scripts/study.py: harness (path),
results (folder), quick, jobs (-j), repeats, extra_sets (--set values every run gets: --quick's
shorter runs).
"""

import concurrent.futures
import os
import shutil
import subprocess
import time
import threading
import sys

from . import reader


def sets_args(sets):
    """["--set", s, ...] for every `KEY=JSON` in sets; an option of the command line itself
    (`--dt-divide=8`: it starts with "--") is passed as it is."""
    return sum(([s] if s.startswith("--") else ["--set", s] for s in sets), [])


# The wall-time cap of a study's run (harness run --max-wall): one that runs longer fails and says
# so (its summary's error) instead of holding the study.
MAX_WALL_S = 1800.0


def harness(a, args, out, check=False, show_stderr=False, cached=True, threads="1"):
    """`harness ARGS` (ARGS writes into `out`), unless `cached` and out/summary.json is there; then
    out's summary. `threads`: HARNESS_THREADS (None: the caller's environment)."""
    if not (cached and reader.has_summary(out)):
        if getattr(a, "cached_only", False):  # study.py --cached-only: a run not made is listed, not made
            return {"status": "not run"}
        env = dict(os.environ, HARNESS_THREADS=threads) if threads else None
        p = subprocess.run([a.harness] + args, check=check, env=env, stderr=None if show_stderr else subprocess.PIPE,
                           text=True)
        if p.returncode == 2 and not reader.has_summary(out):
            # Refused before it ran (exit 2: a dt the stability guard refuses for this force, ...):
            # a configuration that cannot run, listed as failed with the harness's one line.
            why = (p.stderr or "").strip().splitlines()
            return {"status": "refused", "error": why[-1] if why else "exit 2"}
    s = reader.load_summary(out)
    warn_forced(out, s)
    return s


def forcing_cut(s):
    """(the step the run stopped at, the step its forcing ends at or None: never) when the run ended
    before its forcing (drivers, loads, pressure ramps) did (summary window.after_forcing false:
    --quick or --steps cut it short), else None."""
    w = reader.window(s)
    if "after_forcing" not in w or w["after_forcing"]:
        return None
    end = w.get("forcing_ends_step")
    return int(reader.num(w.get("to_step"), reader.steps_run_or_none(s) or 0)), (None if end is None else int(end))


def forced_text(s):
    """"yes" for a run stopped before its forcing ended (forcing_cut), "" otherwise: the `forced`
    column of the studies' and the card's rows."""
    return "yes" if forcing_cut(s) else ""


_warned = set()
_warned_lock = threading.Lock()


def warn_forced(name, s, stream=None):
    """One line on stderr (once per run folder `name`) for a run stopped before its forcing ended:
    its figures are of a body still being loaded. Returns whether it warned."""
    cut = forcing_cut(s)
    with _warned_lock:
        if cut is None or name in _warned:
            return False
        _warned.add(name)
    stop, end = cut
    print("warning: %s stopped at step %d before its forcing ended %s: its figures are of a body still being loaded"
          % (name, stop, "at step %d" % end if end is not None else "(it never ends: a driver without an end)"),
          file=stream or sys.stderr, flush=True)
    return True


def run(a, scene, out, sets, compare=True):
    """One `harness run` of `scene` into `out` without frames, with the --set overrides `sets` (and
    --quick's), compared with results/references/<scene> when that reference exists (`compare` True),
    or with the references `compare` names: (first, second), the second measured beside it
    (--compare-also) where it exists; its summary."""
    from .studies import common  # the user's scene (study.py --scene), if any
    args = ["run", common.scene_arg(a, scene), "--out", out, "--quiet", "--set", "output.frames_every=0",
            "--max-wall", "%g" % getattr(a, "max_wall", MAX_WALL_S)]
    if a.quick:
        args += ["--set", "time.settle.max_steps=400"]
    args += sets_args(list(sets) + a.extra_sets)
    ref, also = (compare[0], compare[1]) if isinstance(compare, (tuple, list)) else (common.reference_dir(a, scene), None)
    if compare and os.path.exists(os.path.join(ref, "surfaces.csv")):
        args += ["--compare", ref]
        if also and os.path.exists(os.path.join(also, "surfaces.csv")):
            args += ["--compare-also", also]
    return harness(a, args, out)


def parallel(a, fn, items):
    """fn(item) for every item, -j at once; the results in order. A line on stderr as each finishes
    (how many of how many, the time so far), so a long study says it is under way."""
    items = list(items)
    done = [0]
    start = time.monotonic()
    lock = threading.Lock()

    def one(item):
        r = fn(item)
        with lock:
            done[0] += 1
            print("study: %d of %d runs done, %.0f s" % (done[0], len(items), time.monotonic() - start),
                  file=sys.stderr, flush=True)
        return r
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        return list(ex.map(one, items))


def run_all(a, jobs):
    """jobs: list of (scene, out, sets[, compare[, timed]]); returns their summaries in order. The
    untimed ones run -j at once; the timed ones (repeated's timing repeats) afterwards one at a
    time, in rounds over the configurations (repeat 1 of each, then repeat 2, ...), so that each
    has the machine to itself and a slow spell falls on all of them alike."""
    out = [None] * len(jobs)
    untimed = [i for i, j in enumerate(jobs) if not (len(j) > 4 and j[4])]
    for i, s in zip(untimed, parallel(a, lambda i: run(a, *jobs[i][:4]), untimed)):
        out[i] = s
    timed = [i for i, j in enumerate(jobs) if len(j) > 4 and j[4]]
    for i in sorted(timed, key=lambda i: (jobs[i][4], i)):
        out[i] = run(a, *jobs[i][:4])
    return out


def run_configs(a, configs, compare=None):
    """configs: (meta, scene, folder under --results/sweeps, sets); runs them -j at once, each compared
    with compare[scene] (run's `compare`: (first, second) reference folders) or, without `compare`,
    with the scene's reference; returns (meta, summary) pairs in order."""
    sums = run_all(a, [(scene, os.path.join(a.results, "sweeps", folder), sets) +
                       ((compare[scene],) if compare is not None else ()) for _, scene, folder, sets in configs])
    return [(c[0], s) for c, s in zip(configs, sums)]


def repeated(a, scene, folder, sets, repeats=None, compare=True):
    """The jobs of a configuration: one error run (folder under --results/sweeps: in full, settled,
    its errors over the window against the reference; not timed) and `repeats` (default --repeats)
    timing runs, folder_t1, folder_t2, ..., every one the same work (the scene's time.steps, no
    references, no settling: a step's time includes no measurement), which run_all executes one at
    a time. The job tuples: (scene, out, sets, compare, timing round or 0); `compare`: the error
    run's references (run). study.py --classes-only: the error run alone (common.committed_timings)."""
    n = 0 if getattr(a, "classes_only", False) else a.repeats if repeats is None else repeats
    timing = [x for x in sets if not x.startswith("references.")] + ["references.solvers=[]", "time.settle=null"]
    return [(scene, os.path.join(a.results, "sweeps", folder), sets, compare, 0)] + [
        (scene, os.path.join(a.results, "sweeps", folder + "_t%d" % r), timing, False, r) for r in range(1, n + 1)]


def reference(a, scene, work, extra=(), quick_levels=3, cached=True):
    """`harness reference SCENE` into `work` (--quick: at most `quick_levels` levels of short runs);
    an error stops the study."""
    args = ["reference", scene, "--out", work, "--quiet"] + list(extra)
    if a.quick:
        args += ["--max-levels", str(quick_levels), "--set", "time.steps=300", "--set", "time.settle.max_steps=400"]
    return harness(a, args, work, check=True, show_stderr=True, cached=cached)


def install_reference(work, dest):
    """A reference's summary.json and surfaces.csv from its work folder into results/references/<name>."""
    os.makedirs(dest, exist_ok=True)
    for f in ["summary.json", "surfaces.csv"]:
        shutil.copy(os.path.join(work, f), os.path.join(dest, f))
