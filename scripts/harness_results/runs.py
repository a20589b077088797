"""The runs scripts/reproduce.sh makes under results/runs/<run>/ (the paper's voxel model on the
bundled scenes, both eliminators), and their frames (frames/*.vtk): read by figures.py, tables.py,
claims/ and counts.py, pruned by prune_frames (scripts/prune_frames.py). Deterministic: fixed run
order, sorted file lists."""

import math
import os
import re

from . import reader

# The runs that scripts/reproduce.sh makes, in the order tables and figures show them:
# (run folder key, bundled scene, title, label of the force setting); each with every eliminator.
SCENES = [
    ("sphere_collision", "sphere_collision", "Sphere collision", "auto"),
    ("cylinder_press", "cylinder_press", "Cylinder press", "auto"),
    ("cylinder_press_f0003", "cylinder_press", "Cylinder press, F = 0.003 N", "0.003 N"),
    ("implant_expansion", "implant_expansion", "Implant expansion", "auto"),
    ("implant_expansion_f0003", "implant_expansion", "Implant expansion, F = 0.003 N", "0.003 N"),
]
ELIMINATORS = ["line", "plane"]

# Instants of the snapshot figures, as fractions of the run (rounded to the nearest frame).
SNAPSHOT_FRACTIONS = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]


def run_name(scene_key, elim):
    return "%s_%s" % (scene_key, elim)


def runs_dir(root):
    return os.path.join(root, "runs")


def existing_runs(root):
    """[(scene_key, scene, title, force_label, elim, path)] for the runs present, in order."""
    out = []
    for key, scene, title, force in SCENES:
        for e in ELIMINATORS:
            p = os.path.join(runs_dir(root), run_name(key, e))
            if os.path.isfile(os.path.join(p, "summary.json")):
                out.append((key, scene, title, force, e, p))
    return out


def by_setting(runs):
    """{scene key: {"scene", "title", "force", "runs": {eliminator: path}}} of existing_runs()."""
    out = {}
    for key, scene, title, force, elim, path in runs:
        out.setdefault(key, {"scene": scene, "title": title, "force": force, "runs": {}})
        out[key]["runs"][elim] = path
    return out


def frames_available(path):
    """{body: sorted list of steps} of the frames present."""
    d = os.path.join(path, "frames")
    out = {}
    if not os.path.isdir(d):
        return out
    for name in sorted(os.listdir(d)):
        m = re.match(r"^(.+)_(\d{6})\.vtk$", name)
        if m:
            out.setdefault(m.group(1), []).append(int(m.group(2)))
    return out


def frame_path(path, body, step):
    return os.path.join(path, "frames", "%s_%06d.vtk" % (body, step))


def snapshot_steps(summary):
    """Steps shown in the snapshot figures: SNAPSHOT_FRACTIONS of the run, rounded to the
    nearest multiple of output.frames_every (the last one is the final step)."""
    n = int(reader.steps_run(summary))
    fe = reader.frames_every(summary)
    steps = []
    for f in SNAPSHOT_FRACTIONS:
        if f >= 1.0 or fe <= 0:
            s = n if f >= 1.0 else 0
        else:
            s = int(math.floor(f * n / fe + 0.5)) * fe
            s = min(s, n)
        if s not in steps:
            steps.append(s)
    return steps


def prune_frames(root):
    """Deletes the frames of the runs under `root` that no figure or table uses: keeps, for every
    body, the snapshot instants of the figures (snapshot_steps: they include step 0 and the last
    step, the ones the tables use for displacements). Returns (kept, removed)."""
    removed = kept = 0
    for _key, _scene, _title, _force, _elim, path in existing_runs(root):
        keep = set(snapshot_steps(reader.load_summary(path)))
        for body, steps in sorted(frames_available(path).items()):
            for s in steps:
                if s in keep:
                    kept += 1
                else:
                    os.remove(frame_path(path, body, s))
                    removed += 1
    return kept, removed


def read_vtk(fname):
    """Legacy ASCII VTK POLYDATA -> (points Nx3 list, triangles Mx3 list, penetrating list or None)."""
    with open(fname) as f:
        tok = f.read().split("\n")
    i = 0
    pts, tris, pen = [], [], None
    while i < len(tok):
        line = tok[i].strip()
        if line.startswith("POINTS"):
            n = int(line.split()[1])
            vals = []
            i += 1
            while len(vals) < 3 * n:
                vals.extend(float(x) for x in tok[i].split())
                i += 1
            pts = [vals[3 * k:3 * k + 3] for k in range(n)]
            continue
        if line.startswith("POLYGONS"):
            n = int(line.split()[1])
            for k in range(n):
                a = tok[i + 1 + k].split()
                tris.append([int(a[1]), int(a[2]), int(a[3])])
            i += n + 1
            continue
        if line.startswith("SCALARS penetrating"):
            i += 1
            if tok[i].strip().startswith("LOOKUP_TABLE"):
                i += 1
            vals = []
            while len(vals) < len(pts) and i < len(tok):
                vals.extend(int(x) for x in tok[i].split())
                i += 1
            pen = vals[:len(pts)]
            continue
        i += 1
    return pts, tris, pen


def steps_row(cols, step):
    """Index of the steps.csv row of `step` (the first row for step 0, which has none)."""
    st = cols["step"]
    target = max(1, step)
    for k, s in enumerate(st):
        if int(s) >= target:
            return k
    return len(st) - 1


def region_at(cols, step):
    """(lo, hi) corners of the voxel region at `step`, None when not recorded."""
    k = steps_row(cols, step)
    lo = [cols["region_lo_%s" % a][k] for a in "xyz"]
    hi = [cols["region_hi_%s" % a][k] for a in "xyz"]
    if not all(reader.present(v) for v in lo + hi):
        return None
    return lo, hi
