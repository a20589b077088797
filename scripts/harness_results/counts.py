"""The counts the report quotes, as LaTeX macros taken from the results (never typed).

Reads only committed files (nothing is run): results/runs/*/summary.json, accuracy_time.csv,
ablation.csv, convergence.csv, realtime.csv, bench.csv. A file that is missing gives "?" for its
macros (the report still builds and shows the hole). Every count has \\Name (digits) and
\\NameWord for prose (one, two, ... twelve, then digits). scripts/study.py rewrites this file
after every study, scripts/reproduce.sh before it builds the report.

  runs (results/runs)        \\NumRuns, \\NumRunSettings (scene and force settings, each run with
                             every eliminator), \\NumRunScenes (bundled scenes), \\NumEliminators,
                             \\NumInstants (instants of the snapshot figures), \\MeasureEvery (steps
                             between two ground-truth measurements)
  accuracy_time.csv          \\AccConfigs, \\AccScenes, \\AccConfigsPerScene, \\AccStable, \\AccFront and
                             per scene (\\AccStableSphere, \\AccFrontCylinder, ...), \\AccRepeats (runs
                             per configuration for the timings; \\AccTimings in words),
                             \\AccVoxelSizes ("2, 4, 8 and 16")
  ablation.csv               \\AblPoints, \\AblPerScene, \\AblForces, \\AblVoxels, \\AblStable and per
                             scene, \\AblVoxelRange ("4 to 32"), \\AblConstRange, \\AblPenaltyRange
  convergence.csv            \\ConvPoints, \\ConvVoxels, \\ConvVoxelRange ("32 to 2")
  realtime.csv               \\RealtimeScenes, \\RealtimeMethods
  bench.csv                  \\BenchSizeMin, \\BenchSizeMax (as powers of ten in math), \\BenchThreads
"""

import os

from . import reader
from . import runs as runs_

WORDS = ["zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven",
         "twelve"]
# Scene -> the suffix of its per-scene macros.
SCENE_TAG = {"sphere_collision": "Sphere", "cylinder_press": "Cylinder", "implant_expansion": "Implant"}


def rows_of(root, name):
    """A CSV file of the results (reader.read_csv), None when missing."""
    return reader.read_csv(os.path.join(root, name), text=reader.STUDY_TEXT)


def listing(values):
    """[2, 4, 8, 16] -> "2, 4, 8 and 16"."""
    v = ["%g" % x for x in values]
    return v[0] if len(v) == 1 else ", ".join(v[:-1]) + " and " + v[-1]


def power_of_ten(n):
    """1000 -> "$10^{3}$"; other numbers as they are."""
    k = len(str(n)) - 1
    return "$10^{%d}$" % k if n == 10 ** k and k >= 2 else "%d" % n


def collect(root):
    """[(name, value)] in a fixed order."""
    out = []

    def count(name, n):
        out.append((name, "?" if n is None else "%d" % n))
        out.append((name + "Word", "?" if n is None else WORDS[n] if 0 <= n < len(WORDS) else "%d" % n))

    def text(name, v):
        out.append((name, "?" if v is None else v))

    # The runs of the report (scripts/reproduce.sh).
    runs = runs_.existing_runs(root)
    count("NumRuns", len(runs))
    count("NumRunSettings", len({r[0] for r in runs}))
    count("NumRunScenes", len({r[1] for r in runs}))
    count("NumEliminators", len({r[4] for r in runs}))
    if runs:
        s = reader.load_summary(runs[0][5])
        count("NumInstants", len(runs_.snapshot_steps(s)))
        count("MeasureEvery", reader.measure_every(s))
    else:
        count("NumInstants", None)
        count("MeasureEvery", None)

    # What accuracy costs in time (scripts/study.py accuracy).
    acc = rows_of(root, "accuracy_time.csv")
    scenes = [] if acc is None else sorted({r["scene"] for r in acc}, key=lambda s: list(SCENE_TAG).index(s)
                                           if s in SCENE_TAG else len(SCENE_TAG))
    count("AccConfigs", None if acc is None else len(acc))
    count("AccScenes", None if acc is None else len(scenes))
    per = sorted({sum(r["scene"] == s for r in acc) for s in scenes}) if acc else []
    text("AccConfigsPerScene", ("%d" % per[0] if len(per) == 1 else "%d--%d" % (per[0], per[-1])) if per else None)
    count("AccStable", None if acc is None else sum(r["stable"] == "yes" for r in acc))
    count("AccFront", None if acc is None else sum(r.get("front") == "yes" for r in acc))
    for scene, tag in SCENE_TAG.items():
        sr = None if acc is None else [r for r in acc if r["scene"] == scene]
        count("AccStable" + tag, None if sr is None else sum(r["stable"] == "yes" for r in sr))
        count("AccFront" + tag, None if sr is None else sum(r.get("front") == "yes" for r in sr))
    reps = sorted({int(r["repeats"]) for r in acc if reader.present(r.get("repeats"))}) if acc else []
    if len(reps) == 1:
        count("AccRepeats", reps[0])
        text("AccTimings", "of one run per configuration" if reps[0] == 1 else
             "the medians of %s runs per configuration" % (WORDS[reps[0]] if reps[0] < len(WORDS) else reps[0]))
    else:
        text("AccRepeats", "%d--%d" % (reps[0], reps[-1]) if reps else None)
        text("AccRepeatsWord", "%d--%d" % (reps[0], reps[-1]) if reps else None)
        text("AccTimings", "the medians of %d to %d runs per configuration" % (reps[0], reps[-1]) if reps else None)
    vox = sorted({float(r["voxel_mm"]) for r in acc if r["detector"] == "voxel" and reader.present(r.get("voxel_mm"))
                  and r["config"].startswith("voxel ")}) if acc else []
    text("AccVoxelSizes", listing(vox) if vox else None)

    # Ablation (scripts/study.py ablation).
    abl = rows_of(root, "ablation.csv")
    count("AblPoints", None if abl is None else len(abl))
    per = sorted({sum(r["scene"] == s for r in abl) for s in {r["scene"] for r in abl}}) if abl else []
    text("AblPerScene", ("%d" % per[0] if len(per) == 1 else "%d--%d" % (per[0], per[-1])) if per else None)
    count("AblForces", None if abl is None else len({r["force"] for r in abl}))
    count("AblVoxels", None if abl is None else len({float(r["voxel_mm"]) for r in abl}))
    count("AblStable", None if abl is None else sum(r["stable"] == "yes" for r in abl))
    for scene, tag in SCENE_TAG.items():
        count("AblStable" + tag, None if abl is None else
              sum(r["stable"] == "yes" for r in abl if r["scene"] == scene))
    if abl:
        v = sorted({float(r["voxel_mm"]) for r in abl})
        text("AblVoxelRange", "%g to %g" % (v[0], v[-1]))
        c = sorted({float(r["force"][2:]) for r in abl if r["force"].startswith("F=")})
        k = sorted({float(r["force"][2:]) for r in abl if r["force"].startswith("k=")})
        text("AblConstRange", "%g to %g" % (c[0], c[-1]) if c else "--")
        text("AblPenaltyRange", "%g to %g" % (k[0], k[-1]) if k else "--")
    else:
        for n in ("AblVoxelRange", "AblConstRange", "AblPenaltyRange"):
            text(n, None)

    # Convergence (scripts/study.py convergence).
    conv = rows_of(root, "convergence.csv")
    count("ConvPoints", None if conv is None else len(conv))
    v = sorted({float(r["voxel_mm"]) for r in conv}) if conv else []
    count("ConvVoxels", len(v) if conv else None)
    text("ConvVoxelRange", "%g to %g" % (v[-1], v[0]) if v else None)

    # Real time by method, mode and threads (scripts/study.py realtime).
    rt = rows_of(root, "realtime.csv")
    count("RealtimeScenes", None if rt is None else len({r["scene"] for r in rt}))
    count("RealtimeMethods", None if rt is None or (rt and "method" not in rt[0]) else len({r["method"] for r in rt}))

    # harness bench (scripts/plot_bench.py).
    b = rows_of(root, "bench.csv")
    sizes = sorted({int(r["nodes"]) for r in b}) if b else []
    text("BenchSizeMin", power_of_ten(sizes[0]) if sizes else None)
    text("BenchSizeMax", power_of_ten(sizes[-1]) if sizes else None)
    th = sorted({int(r["threads"]) for r in b}) if b else []
    text("BenchThreads", " and ".join(WORDS[t] if t < len(WORDS) else "%d" % t for t in th) if th else None)
    return out


def write(root):
    d = os.path.join(root, "tables")
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "counts.tex")
    with open(path, "w") as f:
        f.write("%% generated by scripts/counts.py from %s; do not edit\n" % ", ".join(
            ["runs/", "accuracy_time.csv", "ablation.csv", "convergence.csv", "realtime.csv", "bench.csv"]))
        for name, value in collect(root):
            f.write("\\newcommand{\\%s}{%s}\n" % (name, value))
    print("counts: wrote %s" % path)
    return path
