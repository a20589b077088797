"""The counts the report quotes, as LaTeX macros taken from the results (never typed).

Reads only committed files (nothing is run): results/runs/*/summary.json, accuracy_time.csv,
ablation.csv, convergence.csv, realtime.csv, realtime_grid.csv, bench.csv. A file that is missing gives "?" for its
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
  realtime_grid.csv          per scene (Sphere, Cylinder, Implant) the chosen implicit step \\GridDt (ms),
                             \\GridErrOverBase, \\GridMaxOverBase (window max), \\GridIterations, \\GridCost (baseline steps),
                             \\GridWallPerSim (\\GridWallPerSimTwo: two threads); the explicit step at 0.9 dt_crit's
                             \\GridCritWallPerSim (\\GridCritWallPerSimTwo),
                             \\GridCritErrOverBase; \\GridMachine
  bench.csv                  \\BenchSizeMin, \\BenchSizeMax (as powers of ten in math), \\BenchThreads;
                             per size (Thousand ... Million) \\BenchNsPerSpring, \\BenchStepOverStream,
                             \\BenchStepOverFloor (step / pass_floor), \\BenchFloorNsPerSpring,
                             \\BenchAuditShare, \\BenchStepTwoThreads, \\BenchLawsOverFloor and
                             \\BenchLawsOverStep (step_scene_laws against pass_floor and step)
"""

import csv
import os

from . import reader, rules
from . import runs as runs_

WORDS = ["zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven",
         "twelve"]
# Scene -> the suffix of its per-scene macros.
SCENE_TAG = {"sphere_collision": "Sphere", "cylinder_press": "Cylinder", "implant_expansion": "Implant"}


# results/references/<name> -> the suffix of its macros.
REFERENCE_TAG = {"sphere_collision": "Sphere", "sphere_collision_one_sided": "SphereOneWay",
                 "cylinder_press": "Cylinder", "cylinder_press_one_sided": "CylinderOneWay",
                 "implant_expansion": "Implant", "implant_expansion_one_sided": "ImplantOneWay",
                 "sphere_collision_refined": "SphereRefined"}


SIZE_WORD = {1000: "Thousand", 10000: "TenThousand", 100000: "HundredThousand", 1000000: "Million"}


def figure(v, spec):
    """A figure for prose in `spec` ("%.2g"); None when absent, "--" when not a number."""
    if v is None or v == "":
        return None
    try:
        x = float(v)
    except ValueError:
        return "--"
    return "--" if x != x else spec % x


def mm(v):
    """A length in mm for prose, two significant digits ("0.27", "0.0012", "3.5")."""
    return figure(v, "%.2g")


def num3(v):
    """A figure with three significant digits for prose, never in exponent form (1484 -> "1480")."""
    s = figure(v, "%.3g")
    return "%.0f" % float(s) if s not in (None, "--") and "e" in s else s


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
    """[(name, value)] in a fixed order: one section per source of the report's figures."""
    out = []

    def count(name, n):
        out.append((name, "?" if n is None else "%d" % n))
        out.append((name + "Word", "?" if n is None else WORDS[n] if 0 <= n < len(WORDS) else "%d" % n))

    def text(name, v):
        out.append((name, "?" if v is None else v))

    acc = rows_of(root, "accuracy_time.csv")
    run_counts(root, count)
    accuracy_counts(acc, count, text)
    ablation_counts(rows_of(root, "ablation.csv"), count, text)
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
    reference_counts(root, text)
    best_counts(acc, text, root)
    bench_counts(rows_of(root, "bench.csv"), text)
    grid_counts(rows_of(root, "realtime_grid.csv"), text)
    gpu_counts(root, text)
    return out


def run_counts(root, count):
    """The runs of the report (scripts/reproduce.sh)."""
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


def is_evidence_row(r):
    """A row of accuracy_time.csv that is evidence: stable, not useless (its `useless` column: it
    neither tunnels nor is no better than no force), not the run without contact force."""
    return r["stable"] == "yes" and not r.get("useless") and r["config"] != rules.NO_FORCE


def accuracy_counts(acc, count, text):
    """What accuracy costs in time (scripts/study.py accuracy): configurations, stable ones, the front."""
    scenes = [] if acc is None else sorted({r["scene"] for r in acc}, key=lambda s: list(SCENE_TAG).index(s)
                                           if s in SCENE_TAG else len(SCENE_TAG))
    count("AccConfigs", None if acc is None else len(acc))
    count("AccScenes", None if acc is None else len(scenes))
    per = sorted({sum(r["scene"] == s for r in acc) for s in scenes}) if acc else []
    text("AccConfigsPerScene", ("%d" % per[0] if len(per) == 1 else "%d--%d" % (per[0], per[-1])) if per else None)
    count("AccStable", None if acc is None else sum(r["stable"] == "yes" for r in acc))
    count("AccEvidence", None if acc is None else sum(is_evidence_row(r) for r in acc))
    count("AccFront", None if acc is None else sum(r.get("front") == "yes" for r in acc))
    for scene, tag in SCENE_TAG.items():
        sr = None if acc is None else [r for r in acc if r["scene"] == scene]
        count("AccStable" + tag, None if sr is None else sum(r["stable"] == "yes" for r in sr))
        count("AccEvidence" + tag, None if sr is None else sum(is_evidence_row(r) for r in sr))
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


def ablation_counts(abl, count, text):
    """Ablation (scripts/study.py ablation): points, forces, voxel sizes, stable ones."""
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


def reference_counts(root, text):
    """The references (scripts/study.py references): floors, convergence, one way against both ways."""
    ref = rows_of(root, "references.csv")
    for name, tag in REFERENCE_TAG.items():
        last = [r for r in ref if r["reference"] == name] if ref else []
        last = last[-1] if last else None
        text("Ref%sFloor" % tag, mm(last and last.get("floor_mm")))
        text("Ref%sLevels" % tag, "%d" % (int(last["level"]) + 1) if last else None)
        text("Ref%sConverged" % tag, None if not last else
             "converged" if str(last.get("converged")) in ("True", "true", "yes") else "not converged")
    text("RefGuardViolations", None if not ref else "%d" % sum(int(float(r["guard_violations"] or 0)) for r in ref))
    diff = rows_of(root, "references_differences.csv")
    for key, tag in (("sphere_collision: one way", "OneWaySphere"), ("cylinder_press: one way", "OneWayCylinder"),
                     ("implant_expansion: one way", "OneWayImplant"), ("sphere_collision: mesh refined", "RefinedSphere")):
        row = next((r for r in diff or [] if r["comparison"].startswith(key)), None)
        text("Ref" + tag, mm(row and row["difference_mm"]))
    cylinder_bulk_counts(root, text)
    # The references whose jump is a switch between equilibria (scripts/reference_equilibria.py).
    eq = rows_of(root, "reference_equilibria.csv") if os.path.exists(os.path.join(root, "reference_equilibria.csv")) else None
    for name, tag in (("implant_expansion_one_sided", "ImplantOneWay"), ("cylinder_press", "Cylinder")):
        row = next((r for r in eq or [] if r["reference"] == name), None)
        text("RefEquil%sVerdict" % tag, None if eq is None else row["verdict"] if row else "not tested")
        text("RefEquil%sApart" % tag, mm(row and row["apart_mm"]))
        text("RefEquil%sWithin" % tag, mm(row and max(float(row["a_from_b_to_b_mm"]), float(row["b_from_a_to_a_mm"]))))
        text("RefEquil%sLevels" % tag, None if not row else "%d and %d" % (int(float(row["level_a"])),
                                                                          int(float(row["level_b"]))))


# The variants of results/cylinder_bulk.csv the report names (scripts/cylinder_bulk.py).
CYL_BULK_ALIGNED = "bulk aligned"
CYL_BULK_FIXED = "bulk alternating, cylinder 48 segments"


def cylinder_bulk_counts(root, text):
    """The cylinder's references with a layer that resists inversion (scripts/cylinder_bulk.py): its
    inverted rows, the gap between the two kinds and convergence of the variant that converges."""
    path = os.path.join(root, "cylinder_bulk.csv")
    rows = None
    if os.path.exists(path):
        with open(path) as f:
            rows = list(csv.DictReader(f))
    inv = [int(r["inverted_rows"]) for r in rows or [] if r["variant"].startswith("bulk") and r["kind"].startswith("inversion")]
    text("RefCylVolInverted", None if not inv else "%d" % sum(inv))
    text("RefCylVolRows", None if not rows else next(r["rows"] for r in rows if r["kind"].startswith("inversion")
                                                      and r["variant"].startswith("bulk")))

    def last(variant, kind):
        lv = [r for r in rows or [] if r["variant"] == variant and r["kind"] == kind]
        return lv[-1] if lv else None

    def gap(v):
        g = last(v, "one-sided") and last(v, "one-sided")["kinds_gap_mm"]
        return "less than 0.0001" if g and float(g) < 1e-4 else mm(g)
    text("RefCylVolAlignedGap", gap(CYL_BULK_ALIGNED))
    text("RefCylVolFixedGap", gap(CYL_BULK_FIXED))
    conv = [last(v, k) for v in (CYL_BULK_ALIGNED, CYL_BULK_FIXED) for k in ("two-sided", "one-sided")]
    word = lambda r: None if r is None else "converged" if r["converged"] == "True" else "not converged"
    text("RefCylVolAlignedConverged", None if None in conv[:2] else
         word(conv[0]) + " both ways, " + word(conv[1]) + " one way")
    text("RefCylVolFixedConverged", None if None in conv[2:] else
         word(conv[2]) + " both ways, " + word(conv[3]) + " one way")


def best_of(rows, floor=0.0):
    """The most accurate row, the fastest (t_contact_us) among those within the noise of the least
    error (rules.noise: the chatters, the floor of the references the two rows are measured against,
    `floor` a KindFloor or mm, and the relative tie): what the claims count as equally accurate;
    None if no row."""
    if not rows:
        return None
    t = lambda r: float(r["t_contact_us"]) if reader.present(r.get("t_contact_us")) else float("inf")
    least = min(rows, key=lambda r: (float(r["pos_err_max_mm"]), t(r)))
    num = lambda r: dict(r, pos_err_max_mm=float(r["pos_err_max_mm"]))
    near = [r for r in rows if float(r["pos_err_max_mm"]) <= float(least["pos_err_max_mm"]) + rules.noise(
        num(least), num(r), "pos_err_max_mm", floor)]
    return min(near, key=lambda r: (t(r), float(r["pos_err_max_mm"])))


def kind_floors(root, scene):
    """The floors (mm) of the scene's two references as a rules.KindFloor (reader.reference_floor_mm)."""
    return rules.KindFloor({"both ways": reader.reference_floor_mm(root, scene),
                            "one-sided": reader.reference_floor_mm(root, scene + "_one_sided")})


def best_counts(acc, text, root=None):
    """What accuracy costs: the best error of each family per scene among its evidence (is_evidence_row:
    a stable run that tunnels or does not help is no family's best), the baseline's, times."""
    for scene, tag in SCENE_TAG.items():
        sr = [r for r in acc or [] if r["scene"] == scene]
        base = next((r for r in sr if r["config"] == rules.NO_FORCE), None)
        text("AccNoForce" + tag, kind_mm(base))
        for fam, name in (("voxel", "Voxel"), ("voxel_exact", "VoxelExact"), ("exact", "Exact")):
            dets = ("cgal", "hash") if fam == "exact" else (fam,)
            best = best_of([r for r in sr if r["detector"] in dets and is_evidence_row(r)
                            and reader.present(r.get("pos_err_max_mm"))], kind_floors(root, scene) if root else 0.0)
            text("AccBest%s%s" % (name, tag), None if not sr else kind_mm(best) if best else "--")
            text("AccBest%s%sTime" % (name, tag), None if not sr else num3(best.get("t_contact_us")) if best else "--")
            text("AccBest%s%sMethod" % (name, tag), None if not sr else "--" if not best else
                 "%s, %s, %s" % (best["config"], best["eliminator"], best["force"]))


def kind_mm(row):
    """A row's window position error in mm with the kind of reference it is against ("0.264 one-way",
    "0.0879 both ways"; the table mixes kinds: each method against the reference of its kind)."""
    if not row:
        return mm(None)
    kind = {"one-sided": " one-way", "both ways": " both ways"}.get(row.get("reference") or "", "")
    return mm(row.get("pos_err_max_mm")) + kind


def bench_counts(b, text):
    """harness bench (scripts/plot_bench.py), the CPU's rows (the GPU's: gpu_counts): per size, one
    thread, ns per spring of the step, the step against the streaming pass over what it reads and
    writes and against the force pass floor, and the energy audit's share (step_audited against
    step), in percent."""
    if b:
        b = [r for r in b if r.get("device") in (None, "", "cpu")]
    sizes = sorted({int(r["nodes"]) for r in b}) if b else []
    text("BenchSizeMin", power_of_ten(sizes[0]) if sizes else None)
    text("BenchSizeMax", power_of_ten(sizes[-1]) if sizes else None)

    def at(method, n, threads=1):
        return next((float(r["us_per_step"]) for r in b or [] if r["method"] == method and int(r["nodes"]) == n
                     and int(r["threads"]) == threads and reader.present(r.get("us_per_step"))), None)
    for n, word in SIZE_WORD.items():
        step, stream, audited = at("step", n), at("stream_step", n), at("step_audited", n)
        springs = next((float(r["springs"]) for r in b or [] if r["method"] == "step" and int(r["nodes"]) == n
                        and reader.present(r.get("springs"))), None)
        text("BenchNsPerSpring" + word, None if not b else "%.2g" % (1e3 * step / springs) if step and springs else "--")
        text("BenchStepOverStream" + word, None if not b else "%.2g" % (step / stream) if step and stream else "--")
        floor = at("pass_floor", n)
        text("BenchStepOverFloor" + word, None if not b else "%.2g" % (step / floor) if step and floor else "--")
        text("BenchFloorNsPerSpring" + word, None if not b else "%.2g" % (1e3 * floor / springs)
             if floor and springs else "--")
        text("BenchAuditShare" + word, None if not b else "%.0f" % (100.0 * (audited / step - 1.0))
             if step and audited else "--")
        laws = at("step_scene_laws", n)
        text("BenchLawsOverFloor" + word, None if not b else "%.2g" % (laws / floor) if laws and floor else "--")
        text("BenchLawsOverStep" + word, None if not b else "%.2g" % (laws / step) if laws and step else "--")
        text("BenchStepTwoThreads" + word, None if not b else "%.2g" % (step / at("step", n, 2))
             if step and at("step", n, 2) else "--")
    th = sorted({int(r["threads"]) for r in b}) if b else []
    text("BenchThreads", " and ".join(WORDS[t] if t < len(WORDS) else "%d" % t for t in th) if th else None)


GPU_SIZE_WORD = {**SIZE_WORD, 10000000: "TenMillion"}
SCENE_WORD = {"sphere_collision": "Sphere", "cylinder_press": "Cylinder", "implant_expansion": "Implant"}


def grid_counts(rows, text):
    """The implicit grid (scripts/study.py realtime_grid), per scene: the chosen implicit step (ms), its
    error over the explicit baseline's, its CG iterations (mean), its cost in baseline steps and its wall
    seconds per simulated second (one thread), beside the explicit step at 0.9 dt_crit's; "--" where the
    scene has no such row."""
    for scene, word in SCENE_WORD.items():
        sr = [r for r in rows or [] if r.get("scene") == scene]
        chosen = next((r for r in sr if r.get("chosen") == "yes"), None)
        crit = next((r for r in sr if str(r.get("point")).startswith("explicit")), None)

        def fig(r, key, f="%.2g", scale=1.0):
            return None if rows is None else f % (scale * float(r[key])) if r and reader.present(r.get(key)) else "--"
        text("GridDt" + word, fig(chosen, "dt", "%.2g", 1e3))
        text("GridErrOverBase" + word, fig(chosen, "error_over_best", "%.3g"))
        text("GridMaxOverBase" + word, fig(chosen, "max_over_best", "%.3g"))
        text("GridIterations" + word, fig(chosen, "cg_mean_iterations", "%.0f"))
        text("GridCost" + word, fig(chosen, "cost_in_explicit_steps", "%.1f"))
        text("GridWallPerSim" + word, fig(chosen, "wall_per_sim_s", "%.3g"))
        text("GridCritWallPerSim" + word, fig(crit, "wall_per_sim_s", "%.3g"))
        text("GridCritErrOverBase" + word, fig(crit, "error_over_best", "%.3g"))
        text("GridCritWallPerSimTwo" + word, None if rows is None else "%.3g" % (
            float(crit["t_step_mean_us_t2"]) * 1e-6 / float(crit["dt"])) if crit and reader.present(crit.get("t_step_mean_us_t2")) else "--")
        text("GridWallPerSimTwo" + word, None if rows is None else "%.3g" % (
            float(chosen["t_step_mean_us_t2"]) * 1e-6 / float(chosen["dt"])) if chosen and reader.present(chosen.get("t_step_mean_us_t2")) else "--")
    machine = sorted({r["machine"] for r in rows or [] if r.get("machine")})
    text("GridMachine", None if rows is None else ", ".join(machine) or "--")


def gpu_counts(root, text):
    """The GPU's figures (bench.csv's and realtime.csv's rows whose device is not cpu, and
    device/state_check.csv): the device, per bench size the step against the copy and ns per
    spring, per scene the real-time factors (mean, p99) and the error over the best exact method's,
    and the largest node distance between the GPU's and the CPU's states."""
    b = [r for r in rows_of(root, "bench.csv") or [] if r.get("device") not in (None, "", "cpu")]
    rt = [r for r in rows_of(root, "realtime.csv") or [] if r.get("device") not in (None, "", "cpu")]
    text("GpuDevice", (b or rt)[0]["device"] if (b or rt) else None)

    def at(method, n):
        return next((float(r["us_per_step"]) for r in b if r["method"] == method and int(r["nodes"]) == n), None)
    for n, word in GPU_SIZE_WORD.items():
        step, copy = at("step", n), at("copy", n)
        springs = next((float(r["springs"]) for r in b if r["method"] == "step" and int(r["nodes"]) == n), None)
        text("GpuStepOverCopy" + word, None if not b else "%.2g" % (step / copy) if step and copy else "--")
        text("GpuNsPerSpring" + word, None if not b else "%.2g" % (1e3 * step / springs) if step and springs else "--")
        text("GpuStepUs" + word, None if not b else "%.0f" % step if step else "--")
    for scene, word in SCENE_WORD.items():
        r = next((r for r in rt if r["scene"] == scene), None)
        text("GpuRtf" + word, None if not rt else "%.2g" % float(r["realtime_factor_mean"]) if r else "--")
        text("GpuRtfPnn" + word, None if not rt else "%.2g" % float(r["realtime_factor_p99"]) if r else "--")
        text("GpuStepMeanUs" + word, None if not rt else "%.0f" % float(r["t_step_mean_us"]) if r else "--")
        text("GpuRtfMedian" + word, None if not rt else "%.2g" % float(r["realtime_factor"]) if r else "--")
        text("GpuStepMedianUs" + word, None if not rt else "%.0f" % float(r["t_step_us"]) if r else "--")
        text("GpuTwinErrOverBest" + word, None if not rt else "%.3g" % float(r["cpu_twin_error_over_best"]) if r else "--")
    sc = rows_of(root, os.path.join("device", "state_check.csv")) or []
    text("GpuStateChecks", "%d" % len(sc) if sc else None)
    text("GpuStateIdentical", "%d" % sum(1 for r in sc if r["bit_identical"] == "true") if sc else None)
    far = max((float(r["max_node_distance_m"]) for r in sc), default=None)
    text("GpuStateMaxDistance", "%.2g" % far if far is not None else None)


def write(root):
    d = os.path.join(root, "tables")
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "counts.tex")
    with open(path, "w") as f:
        f.write("%% generated by scripts/counts.py from %s; do not edit\n" % ", ".join(
            ["runs/", "accuracy_time.csv", "ablation.csv", "convergence.csv", "realtime.csv", "realtime_grid.csv",
             "bench.csv", "device/state_check.csv"]))
        for name, value in collect(root):
            f.write("\\newcommand{\\%s}{%s}\n" % (name, value))
    print("counts: wrote %s" % path)
    return path
