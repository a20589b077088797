"""harness from Python: scenes, runs and a simulation you can step (docs/python.md).

    import harness
    scene = harness.Scene.load("sphere_collision").with_(**{"contacts.0.detector": "voxel"})
    result = harness.run(scene, steps=200)          # what `harness run` writes, read back
    sim = harness.Simulation(scene)
    sim.step(100)
    x = sim.positions("left")                      # read-only (n, 3) view, follows the steps

Bad input raises SceneError, whose message is the command line's exit-2 line (file and key path).
"""
import csv
import gzip
import json
import operator
import os
import shutil
import sys
import tempfile

try:
    import numpy as np
except ImportError:  # one line, not a traceback (the module's arrays are numpy's)
    print("harness: needs numpy (Debian's python3-numpy); run it with /usr/bin/python3 or set PYTHON", file=sys.stderr)
    raise SystemExit(2)

from ._harness import Scene, SceneError, Simulation, SimulationError, have_reference
from ._harness import _run_scene

__all__ = ["Scene", "SceneError", "Simulation", "SimulationError", "Result", "run", "read_steps",
           "have_reference", "penalty_response"]


# steps.csv's columns of words: always str, also where every row is empty (a scene without contacts).
TEXT_COLUMNS = ("pair", "detector")


def _read_rows(path):
    """The rows of a CSV file stored plain or gzipped (PATH or PATH.gz); None when neither is there."""
    for p in (path, path + ".gz"):
        if os.path.isfile(p):
            with (gzip.open(p, "rt", newline="") if p.endswith(".gz") else open(p, newline="")) as f:
                return list(csv.reader(f))
    return None


def read_steps(path):
    """steps.csv (or steps.csv.gz) as a dict of column name -> numpy array (float where every value
    is a number, else str; an empty field in a numeric column is NaN; `pair` and `detector` always
    str), with the wall times of timing.csv beside it (keyed by step and pair, row for row) joined."""
    rows = _read_rows(path)
    if rows is None:
        raise FileNotFoundError(f"{path}: no such file (nor {path}.gz)")
    timing = _read_rows(os.path.join(os.path.dirname(path), "timing.csv"))
    if timing and len(timing) != len(rows):
        raise ValueError(f"{path}: timing.csv has {len(timing) - 1} rows, steps.csv {len(rows) - 1}")
    if timing and rows:
        keys = [rows[0].index(k) for k in ("step", "pair") if k in rows[0]]
        extra = [j for j, name in enumerate(timing[0]) if name not in ("step", "pair")]
        for i, (r, t) in enumerate(zip(rows, timing)):
            if i and [r[k] for k in keys] != t[:len(keys)]:
                raise ValueError(f"{path}: timing.csv row {i} does not match steps.csv's")
            r.extend(t[j] for j in extra)
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    out = {}
    for j, name in enumerate(header):
        values = [r[j] if j < len(r) else "" for r in body]
        if name in TEXT_COLUMNS:
            out[name] = np.array(values, dtype=str)
            continue
        try:
            out[name] = np.array([float(v) if v != "" else np.nan for v in values], dtype=float)
        except ValueError:
            out[name] = np.array(values, dtype=str)
    return out


def penalty_response(k):
    """The built-in linear penalty written as a response of your own (docs/python.md): per contact
    k max(0, depth) along the push's direction on its node, and the reaction on the nodes it pushes
    against shared by their weights; both ways of a two-sided pair. A template for your own rule:
    response(contacts, guest, host) -> (forces on the guest, forces on the host), each (n, 3), N."""
    k = float(k)

    def penalty(contacts, guest, host):
        fg, fh = np.zeros_like(guest["x"]), np.zeros_like(host["x"])
        f = k * np.maximum(contacts["depth"], 0.0)[:, None] * contacts["direction"]
        f[contacts["hosts"][:, 0] < 0] = 0.0  # nothing to push against: no force
        for way, (own, other) in enumerate(((fg, fh), (fh, fg))):
            sel = contacts["way"] == way
            np.add.at(own, contacts["node"][sel], f[sel])
            for j in range(3):
                s = sel & (contacts["hosts"][:, j] >= 0)
                np.add.at(other, contacts["hosts"][s, j], -contacts["weights"][s, j, None] * f[s])
        return fg, fh

    penalty.__qualname__ = f"penalty_response({k:g})"
    return penalty


class Result:
    """A finished run: .summary (summary.json as a dict), .steps (steps.csv's columns as numpy
    arrays), .state_hash, .exit_code (0 done, 3 the state became non-finite: .summary says
    where), .out (the folder it was written to, None when it was a temporary one)."""

    def __init__(self, summary, steps, exit_code, out):
        self.summary = summary
        self.steps = steps
        self.exit_code = exit_code
        self.out = out

    @property
    def state_hash(self):
        return self.summary.get("state_hash")

    def __repr__(self):
        status = self.summary.get("status")
        return (f"<harness.Result {self.summary.get('scene', '?')}: "
                f"{self.summary.get('steps_run', '?')} steps, status {status}, "
                f"state_hash {self.state_hash}>")


def _as_scene(scene):
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, dict):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    raise TypeError(f"expected a harness.Scene, a dict or a scene file/name, got {type(scene).__name__}")


def run(scene, steps=None, threads=1, compare=None, out=None, compare_also=None, response=None):
    """Runs a scene as `harness run` does (the same code, the same files) and returns a Result.

    steps: exactly that many steps (time.settle off), as --steps; None: the scene's own.
    threads: threads of the parallel kernels (results do not depend on it).
    compare: a reference folder (harness reference) or a finished run of the same scene.
    compare_also: with compare, a second reference measured on the same steps (--compare-also: the
    other kind, one way against both ways): summary error_vs_reference_also, steps also_* columns.
    out: the output folder (as --out); None: a temporary folder, removed after reading it back.
    response: a contact response of your own instead of the scene's force rule, as for Simulation
    (a callable for every pair, or a dict of pair label or index -> callable): the same folder as
    the command line writes, with summary.json pairs[].response naming it, which --compare, the
    card and the studies accept. An exception it raises is raised here, after the outputs of the
    steps before it are written (summary status "failed").
    Raises SceneError for bad input (nothing written), KeyboardInterrupt when interrupted (the
    outputs in `out` hold the state after the last whole step, summary status "interrupted"; with
    out=None the temporary folder is kept and named), SystemExit(143) when terminated (SIGTERM).
    The run's warnings go to the process's standard error, as the command line's do.
    """
    scene = _as_scene(scene)
    if steps is not None:
        scene = scene.with_steps(operator.index(steps))
    threads = operator.index(threads)
    if threads < 1:
        raise ValueError("threads: must be >= 1")
    folder = os.fspath(out) if out is not None else tempfile.mkdtemp(prefix="harness-run-")
    keep = out is not None
    try:
        rc = _run_scene(scene, folder, threads, os.fspath(compare) if compare is not None else "",
                        os.fspath(compare_also) if compare_also is not None else "", response)
        if rc in (130, 143):
            keep = True
            if rc == 143:
                raise SystemExit(143)
            raise KeyboardInterrupt(f"harness.run: interrupted; outputs in {folder}")
        with open(os.path.join(folder, "summary.json")) as f:
            summary = json.load(f)
        table = read_steps(os.path.join(folder, "steps.csv"))
    finally:
        if not keep:
            shutil.rmtree(folder, ignore_errors=True)
    return Result(summary, table, rc, folder if out is not None else None)
