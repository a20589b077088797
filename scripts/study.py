#!/usr/bin/env python3
"""The studies of the report, all judged by the error against a converged reference solution.

  study.py references   results/references/<scene>/ (summary.json with every level of the loop,
                        surfaces.csv: the settled reference), tables/references.{md,tex}
  study.py accuracy     accuracy_time.csv, figures/pareto_<scene>.{png,pdf}, tables/accuracy_time.md,
                        tables/accuracy_time_front.tex: what accuracy costs in time
  study.py ablation     ablation.csv, figures/ablation_<scene>.{png,pdf}, tables/ablation.md,
                        tables/ablation_defaults.tex: force rule and magnitude by voxel size, the
                        voxel model's default chosen by the written rule
  study.py convergence  convergence.csv, figures/convergence.{png,pdf}, tables/convergence.md
  study.py refinement   refinement.csv, tables/refinement.{md,tex}: settled shape against mesh resolution
  study.py realtime     realtime.csv, tables/realtime.{md,tex}: steps per second, one core
  study.py swap         swap.csv, tables/swap.md: host and guest swapped (which body carries the grid)
  study.py region       region.csv, tables/region.md: claim (e), region half/full/overlap x margin
  study.py all          every one of them, in this order (or name several: study.py accuracy realtime)
Options: --harness PATH (default build/bin/harness), --results DIR (default results),
         --quick (short runs, fewer points: a smoke test, not results), -j N (runs at once, default 2),
         --repeats N (runs per configuration for the timings, default 3),
         --plots-only (runs nothing: redraws the figures of accuracy, ablation and convergence from
         accuracy_time.csv, ablation.csv and convergence.csv in --results; the others have none).
Every study ends by rewriting tables/counts.tex (scripts/counts.py: the counts the report quotes).

Definitions (stated once, used everywhere):
  window        the final time.window steps of a run (default 1000), after every driver, load and
                pressure ramp has finished (core/run/window.hpp); every run is measured by CGAL every
                STUDY_EVERY = 10 steps (one sampling rule for runs, sweeps and studies).
  error         against the scene's reference (core/run/compare.hpp), over the window: pos_err_max (largest
                distance of a surface vertex from where the reference has it) as its window mean, with
                its window maximum and chatter amplitude (max - min); gap_max (largest gap where the
                reference has contact) window mean; depth_max (deepest node inside the other body)
                window maximum, and its peak over the whole run; tunnelled nodes (through the other
                body) window maximum.
  stable        by the run's contact power over the window against the power the scene put in
                (rho, summary.json window.contact_power_ratio; the harness calls a run "injects"
                above 0.02) with a stated margin of a factor 2 either way: stable when the run
                settled or chatters with rho <= 0.01; unstable when rho > 0.04, when its kinetic
                energy grows over the window, when contact kicked the bodies (its net work still
                held as motion), when dt exceeded the guard or the state went non-finite; marginal
                in between (0.01 < rho <= 0.04). A verdict that rests on a run that is not stable is
                "inconclusive". The energy audit must close within 1 % for the figures to count.
  time          microseconds per step of detection plus elimination (t_contact) and of the whole
                step (t_step): the median over the run's steps, then the median over --repeats runs
                (the spread is the range over the runs).
  rule          (the defaults) among the stable settings whose pos_err_max or depth_max is at most 90 %
                of the run without contact force (a default must do something), the smallest pos_err_max; among
                those within 10 % of it, the smallest gap_max; among those, the fastest. None such:
                no default (and no CI threshold) for that scenario, said in ablation.md.
"""
import argparse, concurrent.futures, csv, json, math, os, shutil, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import counts  # noqa: E402
import resultslib as rl  # noqa: E402

plt = rl.pyplot()

SCENES = ["sphere_collision", "cylinder_press", "implant_expansion"]
# The paper's eliminator for each scenario (line for the spheres and the cylinder, plane for the implant).
PAPER_ELIMINATOR = {"sphere_collision": "line", "cylinder_press": "line", "implant_expansion": "plane"}
VOXELS = [0.002, 0.004, 0.008, 0.016]
ABLATION_VOXELS = [0.004, 0.008, 0.016, 0.032]
CONVERGENCE_VOXELS = [0.032, 0.016, 0.008, 0.004, 0.002]
CONVERGENCE_VOXELS_MM = [1e3 * v for v in CONVERGENCE_VOXELS]
CONSTANT_FORCES = ["0.003", "0.01", "0.03", "0.1"]
PENALTY = '{"stiffness":500}'
CONSTANT = "0.01"
ABLATION_FORCES = CONSTANT_FORCES + ["auto", '{"stiffness":125}', PENALTY, '{"stiffness":2000}']
# Stability by the contact's power over the window against the power put in (core/run/window.hpp,
# whose own limit is INJECTION_LIMIT), with a margin of a factor MARGIN either way.
INJECTION_LIMIT = 0.02
MARGIN = 2.0
BALANCE = 0.01
# Every run of every study is measured by CGAL every STUDY_EVERY steps (and scripts/reproduce.sh's
# runs too): one sampling rule, so that recall and the window figures mean the same everywhere.
STUDY_EVERY = 10
WITHIN = 1.10
# A default must do something: its position error or its depth at most this share of the run
# without contact force (the same scene, contact detected but never pushed).
USEFUL = 0.9


def force_label(f):
    if f == "auto":
        return "auto"
    if f.startswith("{"):
        return "k=%g" % json.loads(f)["stiffness"]
    return "F=%s" % f


# ---------------------------------------------------------------------------------------------
# Running
def run_one(a, scene, out, sets, compare=True):
    """One `harness run` into `out` (skipped when its summary is already there); its summary."""
    summary = os.path.join(out, "summary.json")
    if not os.path.exists(summary):
        cmd = [a.harness, "run", scene, "--out", out, "--quiet", "--set", "output.frames_every=0"]
        if a.quick:
            cmd += ["--set", "time.settle.max_steps=400"]
        for s in sets + a.extra_sets:
            cmd += ["--set", s]
        ref = os.path.join(a.results, "references", scene)
        if compare and os.path.exists(os.path.join(ref, "surfaces.csv")):
            cmd += ["--compare", ref]
        env = dict(os.environ, HARNESS_THREADS="1")
        subprocess.run(cmd, check=False, env=env, stderr=subprocess.DEVNULL)
    with open(summary) as f:
        return json.load(f)


def run_all(a, jobs):
    """jobs: list of (scene, out, sets[, compare]); runs them -j at once; returns their summaries in order."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        return list(ex.map(lambda j: run_one(a, *j), jobs))


def num(v, default=float("nan")):
    try:
        return float(v)
    except (TypeError, ValueError):
        return default


def classify(s):
    """(class, reasons) of one run's summary by the written rule (module docstring): "stable",
    "marginal", "unstable" or "failed"."""
    w = s.get("window") or {}
    en = s.get("energy") or {}
    st = s.get("stability") or {}
    rho = num(w.get("contact_power_ratio"))
    verdict = s.get("stability_verdict")
    if s.get("status") != "ok":
        return "failed", ["not finite" if s.get("finite") is False else str(s.get("status"))]
    reasons = []
    if num(st.get("guard_violations"), 0) > 0:
        reasons.append("dt above the limit")
    if verdict == "grows":
        reasons.append("kinetic energy grows over the window (x%.3g)" % num(w.get("kinetic_growth")))
    if w.get("kicked"):
        reasons.append("contact kicked the bodies (net work %.3g J still held as motion)" % num(w.get("net_contact_work_J")))
    if not math.isnan(rho) and rho > INJECTION_LIMIT * MARGIN:
        reasons.append("contact power %.3g of the power put in" % rho)
    if abs(num(en.get("energy_balance_error"), 0.0)) > BALANCE:
        reasons.append("energy audit open")
    if reasons:
        return "unstable", reasons
    if verdict != "settled" and not math.isnan(rho) and rho > INJECTION_LIMIT / MARGIN:
        return "marginal", ["contact power %.3g of the power put in (within a factor %g of %g)" % (rho, MARGIN, INJECTION_LIMIT)]
    return "stable", []


def wstat(d, key, what="mean"):
    """A window statistic (summary.json window figures) or nan."""
    v = (d or {}).get(key) or {}
    return num(v.get(what)) if isinstance(v, dict) else float("nan")


def figures(s):
    """The figures of one run's summary that the studies use (module docstring: window, error, stable)."""
    p = s["pairs"][0] if s.get("pairs") else {}
    e = p.get("error_vs_reference") or {}
    ew = e.get("window") or {}
    w = s.get("window") or {}
    t = s.get("timing_us") or {}
    cls, reasons = classify(s)
    mm = lambda v: 1e3 * v
    return {
        "status": s.get("status"), "stable": "yes" if cls == "stable" else "no", "stability": cls,
        "why_unstable": "; ".join(reasons), "verdict": s.get("stability_verdict"),
        "contact_power_ratio": num(w.get("contact_power_ratio")),
        "settled": s.get("settled"), "steps": s.get("steps_run"), "window_from": w.get("from_step"),
        "pos_err_max_mm": mm(wstat(ew, "pos_err_max")), "pos_err_max_max_mm": mm(wstat(ew, "pos_err_max", "max")),
        "pos_err_amp_mm": mm(wstat(ew, "pos_err_max", "amplitude")), "pos_err_final_mm": mm(num(e.get("pos_err_max"))),
        "pos_err_rms_mm": mm(wstat(ew, "pos_err_rms")),
        "gap_max_mm": mm(wstat(ew, "gap_max")), "gap_mean_mm": mm(wstat(ew, "gap_mean")),
        "depth_max_mm": mm(wstat(ew, "depth_max", "max")), "depth_peak_mm": mm(num(e.get("depth_peak"))),
        "tunnelled": wstat(ew, "tunnelled", "max"), "tunnelled_peak": num(e.get("tunnelled_peak")),
        "t_contact_us": num(t.get("detect"), 0.0) + num(t.get("eliminate"), 0.0), "t_step_us": num(t.get("step")),
        "recall": num(p.get("recall")), "precision": num(p.get("precision")),
        "recall_host": num(p.get("recall_host")), "precision_host": num(p.get("precision_host")),
        "true_pen_final": num(p.get("true_pen_final")), "voxel_size_used": num(p.get("voxel_size_used")),
        "beyond_band_total": num(p.get("beyond_band_total")),
    }


def run_configs(a, configs):
    """configs: (meta, scene, folder under --results/sweeps, sets); runs them -j at once; returns
    (meta, summary) pairs in order."""
    sums = run_all(a, [(scene, os.path.join(a.results, "sweeps", folder), sets) for _, scene, folder, sets in configs])
    return [(c[0], s) for c, s in zip(configs, sums)]


def repeated(a, scene, folder, sets, repeats=None):
    """A configuration run `repeats` (default --repeats) times: the first in full (its errors over the
    window, against the reference); the others for their timings only (time.steps without settling,
    no references: a step's time does not include measurement)."""
    n = a.repeats if repeats is None else repeats
    outs = [os.path.join(a.results, "sweeps", folder + ("" if r == 0 else "_r%d" % r)) for r in range(n)]
    timing = [x for x in sets if not x.startswith("references.")] + ["references.solvers=[]", "time.settle=null"]
    return [(scene, o, sets if r == 0 else timing, r == 0) for r, o in enumerate(outs)]


def combine(summaries):
    """Errors of the first run; contact and step time: median over the runs' medians, and the range."""
    f = figures(summaries[0])
    tc = sorted(figures(s)["t_contact_us"] for s in summaries)
    ts = sorted(figures(s)["t_step_us"] for s in summaries)
    f["t_contact_us"] = rl.median(tc)
    f["t_contact_range"] = "%.3g-%.3g" % (tc[0], tc[-1])
    f["t_step_us"] = rl.median(ts)
    f["repeats"] = len(summaries)
    return f


def useful(r, base):
    """At least 10 % closer to the reference than the run without contact force, in position or in depth."""
    return (r["pos_err_max_mm"] <= USEFUL * base["pos_err_max_mm"]
            or r["depth_max_mm"] <= USEFUL * base["depth_max_mm"])


def choose(rows, baseline=None):
    """The written rule (module docstring) over stable rows; None when none is stable (or, given the
    run without contact force, when no stable row is clearly closer to the reference than it)."""
    ok = [r for r in rows if r["stable"] == "yes" and not math.isnan(r["pos_err_max_mm"])]
    if baseline is not None:
        ok = [r for r in ok if useful(r, baseline)]
    if not ok:
        return None
    best = min(r["pos_err_max_mm"] for r in ok)
    near = [r for r in ok if r["pos_err_max_mm"] <= WITHIN * best]
    g = min(r["gap_max_mm"] for r in near)
    near = [r for r in near if r["gap_max_mm"] <= WITHIN * g + 1e-9]
    return min(near, key=lambda r: r["t_contact_us"])


def pareto(rows, x="t_contact_us", y="pos_err_max_mm"):
    ok = [r for r in rows if r["stable"] == "yes" and not math.isnan(r[x]) and not math.isnan(r[y])]
    return [r for r in ok if not any(o is not r and o[x] <= r[x] and o[y] <= r[y] and (o[x] < r[x] or o[y] < r[y])
                                     for o in ok)]


# ---------------------------------------------------------------------------------------------
# The references: each bundled scene both ways (the answer of physics, which every study is judged
# against) and one way (the paper's model keeps only the guest's nodes out of the host), and one
# scene on a refined mesh (its change from the base mesh: the mesh's share of every error).
REFINED_SCENE = "sphere_collision"


def reference_runs():
    """(name, scene, extra harness reference arguments) of every committed reference."""
    out = []
    for scene in SCENES:
        out.append((scene, scene, []))
        out.append((scene + "_one_sided", scene, ["--one-sided"]))
    sets = sum((["--set", x] for x in refine_sets(REFINED_SCENE, 2)), [])
    out.append((REFINED_SCENE + "_refined", REFINED_SCENE, sets + ["--dt-divide", "2"]))
    return out


def surface_difference(a_dir, b_dir, match_rest=False):
    """Largest distance (m) between the settled surfaces of two references: vertex by vertex (the same
    mesh), or (match_rest) at the vertices of the first whose rest position the second has too (a
    mesh refined by subdivision keeps its base vertices); and how many vertices were compared."""
    A, B = rl.load_surfaces(a_dir), rl.load_surfaces(b_dir)
    worst, n = 0.0, 0
    for body, va in A.items():
        vb = B.get(body, [])
        if not match_rest:
            for p, q in zip(va, vb):
                worst, n = max(worst, math.dist(p[:3], q[:3])), n + 1
            continue
        at = {tuple(round(c, 12) for c in q[3:6]): q for q in vb}
        for p in va:
            q = at.get(tuple(round(c, 12) for c in p[3:6]))
            if q is not None:
                worst, n = max(worst, math.dist(p[:3], q[:3])), n + 1
    return worst, n


def references(a):
    rows = []
    for name, scene, extra in reference_runs():
        work = os.path.join(a.results, "sweeps", "references", name)
        dest = os.path.join(a.results, "references", name)
        if not os.path.exists(os.path.join(work, "summary.json")):
            cmd = [a.harness, "reference", scene, "--out", work, "--quiet"] + extra
            if a.quick:
                cmd += ["--max-levels", "3", "--set", "time.steps=300", "--set", "time.settle.max_steps=400"]
            subprocess.run(cmd, check=True, env=dict(os.environ, HARNESS_THREADS="1"))
        os.makedirs(dest, exist_ok=True)
        for f in ["summary.json", "surfaces.csv"]:
            shutil.copy(os.path.join(work, f), os.path.join(dest, f))
        with open(os.path.join(dest, "summary.json")) as f:
            ref = json.load(f)["reference"]
        for lv in ref["levels"]:
            dt_crit_min = num(lv.get("dt_crit_min"))
            rows.append({"reference": name, "level": lv["level"], "dt": lv["dt"], "stiffness": lv["stiffness"],
                         "substeps_max": lv.get("max_substeps"), "guard_violations": lv.get("guard_violations"),
                         "h_over_dt_crit_min": lv["dt"] / num(lv.get("max_substeps"), 1) / dt_crit_min if dt_crit_min > 0 else float("nan"),
                         "steps": lv["steps_run"], "settled": lv["settled"], "residual": lv["residual"],
                         "change_mm": 1e3 * num(lv["change_max"]), "order": num(lv.get("order")),
                         "error_estimate_mm": 1e3 * num(lv.get("error_estimate")), "wall_s": lv["wall_s"],
                         "converged": ref["converged"] if lv is ref["levels"][-1] else ""})
    cols = ["reference", "level", "dt", "stiffness", "substeps_max", "h_over_dt_crit_min", "guard_violations", "steps",
            "settled", "residual", "change_mm", "order", "error_estimate_mm", "wall_s", "converged"]
    rl.write_csv(os.path.join(a.results, "references.csv"), rows, cols)
    # How far apart the answers are: one way against both ways (same mesh), refined against base.
    diffs = []
    for scene in SCENES:
        d, n = surface_difference(os.path.join(a.results, "references", scene),
                                  os.path.join(a.results, "references", scene + "_one_sided"))
        diffs.append({"comparison": "%s: one way against both ways" % scene, "difference_mm": 1e3 * d, "vertices": n})
    d, n = surface_difference(os.path.join(a.results, "references", REFINED_SCENE),
                              os.path.join(a.results, "references", REFINED_SCENE + "_refined"), match_rest=True)
    diffs.append({"comparison": "%s: mesh refined (x2) against base, at the base vertices" % REFINED_SCENE,
                  "difference_mm": 1e3 * d, "vertices": n})
    rl.write_csv(os.path.join(a.results, "references_differences.csv"), diffs, ["comparison", "difference_mm", "vertices"])
    heads = ["reference", "level", "dt (s)", "k_c (N/m)", "substeps (max)", "h / dt_crit (min)", "guard violations",
             "steps", "settled", "residual", "change (mm)", "order", "error estimate (mm)", "wall (s)", "converged"]
    with open(os.path.join(a.results, "tables", "references.md"), "w") as f:
        f.write("# Reference solutions\n\nExact detection (CGAL), contact both ways (`_one_sided`: the guest's nodes "
                "kept out of the host only, as the paper's model does), penalty k_c x depth with barycentric "
                "reactions; each level halves dt and doubles k_c over the same physical time, under the stability "
                "guard `substep` (no substep above 0.9 dt_crit, the penalty's stiffness counted; h / dt_crit is the "
                "substep over the smallest dt_crit the guard saw), and settles to the scene's own tolerance (the "
                "one its runs settle to); change = largest distance of a surface vertex between the level and the "
                "one before; order = log2 of the ratio of the last two changes; error estimate = change / "
                "(2^order - 1) (Richardson). Converged when the change is below 0.05 mm after at least three "
                "levels. `%s_refined`: the scene on a mesh refined once (dt halved). Made by `scripts/study.py "
                "references`.\n\n" % REFINED_SCENE + rl.md_table(rows, cols, heads) +
                "\n\n## How far apart the answers are\n\n" +
                rl.md_table(diffs, ["comparison", "difference_mm", "vertices"],
                            ["comparison", "largest difference (mm)", "vertices compared"]))
    with open(os.path.join(a.results, "tables", "references.tex"), "w") as f:
        f.write(rl.tex_table([dict(r, reference=r["reference"].replace("_", " ")) for r in rows],
                             ["reference", "level", "dt", "stiffness", "h_over_dt_crit_min", "steps", "change_mm", "order",
                              "converged"],
                             ["reference", "level", "$\\Delta t$ (s)", "$k_c$ (N/m)", "$h/\\Delta t_{crit}$", "steps",
                              "change (mm)", "order", "converged"], "The reference loop"))


# ---------------------------------------------------------------------------------------------
# The equal-footing comparison: the paper's voxel model with voxels at or above the host's node
# spacing (host mean surface edge: sphere 3.0 mm, layer 5.7 mm, implant 6.1 mm: the smallest
# power of two above it and twice it), forces from 0.0005 to 0.01 N and `auto`, line and plane;
# the completed model (voxel_exact) with its voxel swept one size further; spatial hashing, CGAL
# and FCL with the same responses.
FOOTING_VOXELS = {"sphere_collision": [0.004, 0.008], "cylinder_press": [0.008, 0.016],
                  "implant_expansion": [0.008, 0.016]}
FOOTING_FORCES = ["0.0005", "0.001", "0.003", "0.01", "auto"]
BOTH_WAYS = ["contacts.0.two_sided=true"]


def method_configs(scene):
    """(label, detector, voxel size or None, eliminator, force, extra sets) of the comparison."""
    out = []
    voxels = FOOTING_VOXELS[scene]
    for v in voxels:
        label = "voxel %g mm" % (1e3 * v)
        for e in ["line", "plane"]:
            for f in FOOTING_FORCES:
                out.append((label, "voxel", v, e, f, []))
        out.append((label, "voxel", v, "line", PENALTY, []))
        out.append((label, "voxel", v, "projection", "auto", []))
    for v in voxels + [2 * voxels[-1]]:
        label = "voxel_exact %g mm" % (1e3 * v)
        out.append((label, "voxel_exact", v, "line", "auto", []))
        out.append((label, "voxel_exact", v, "line", PENALTY, []))
        out.append((label + ", both ways", "voxel_exact", v, "line", PENALTY, BOTH_WAYS))
    for d in ["hash", "cgal", "fcl"]:
        for f in ["auto", PENALTY]:
            out.append((d, d, None, "line", f, []))
        out.append((d, d, None, "projection", "auto", []))
    for d in ["hash", "cgal"]:
        out.append((d + ", both ways", d, None, "line", PENALTY, BOTH_WAYS))
    return out


def config_sets(det, voxel, elim, force, extra):
    sets = ['contacts.0.detector="%s"' % det, 'contacts.0.eliminator="%s"' % elim, "contacts.0.force=" +
            (json.dumps(force) if force == "auto" else force), "contacts.0.two_sided=false",
            'references.solvers=["cgal"]', "references.every=%d" % STUDY_EVERY]
    if voxel:
        sets.append("contacts.0.voxel_size=%g" % voxel)
    return sets + extra


def folder_name(scene, label, elim, force):
    return "%s/%s_%s_%s" % (scene, label.replace(" ", "_").replace(",", ""), elim, force_label(force))


def accuracy(a):
    rows, jobs, index = [], [], []
    for scene in SCENES:
        for label, det, voxel, elim, force, extra in method_configs(scene):
            js = repeated(a, scene, "accuracy/" + folder_name(scene, label, elim, force),
                          config_sets(det, voxel, elim, force, extra))
            index.append((scene, label, det, voxel, elim, force, len(jobs), len(js)))
            jobs += js
    sums = run_all(a, jobs)
    for scene, label, det, voxel, elim, force, i, n in index:
        rows.append(dict(combine(sums[i:i + n]), scene=scene, config=label, detector=det, eliminator=elim,
                         force=force_label(force) if elim != "projection" else "positions"))
    cols = ["scene", "config", "detector", "eliminator", "force", "stable", "why_unstable", "settled", "steps",
            "pos_err_max_mm", "pos_err_max_max_mm", "pos_err_amp_mm", "pos_err_final_mm", "pos_err_rms_mm", "gap_max_mm",
            "gap_mean_mm", "depth_max_mm", "depth_peak_mm", "tunnelled", "stability", "verdict", "contact_power_ratio",
            "recall", "precision", "t_contact_us", "t_contact_range", "t_step_us", "repeats"]
    for r in rows:
        r["front"] = ""
    md = ["# What accuracy costs in time\n\n",
          "Every method on every scenario, judged by its error against the scenario's reference solution "
          "(`results/references/`) over the run's final window (`time.window` steps after every driver and "
          "load has finished; CGAL every %d steps): pos_err_max: largest distance of a surface vertex from "
          "the reference, window mean (max and chatter amplitude beside it); gap_max: largest gap where the "
          "reference has contact, window mean; depth_max: deepest node inside the other body, window maximum; "
          "tunnelled: nodes through the other body; all in mm. Time: detection plus elimination, µs per step, "
          "median of %d runs (range over them). Stability (scripts/study.py docstring): the contact's power "
          "over the window against the power put in, rho, with a margin of a factor %g around %g: stable "
          "(settled, or chatters with rho <= %g), marginal, unstable. The Pareto front (error against time) "
          "is drawn from the stable rows only; every row is listed with its rho and reason. Made by "
          "`scripts/study.py accuracy`.\n"
          % (STUDY_EVERY, a.repeats, MARGIN, INJECTION_LIMIT, INJECTION_LIMIT / MARGIN)]
    for scene in SCENES:
        sr = [r for r in rows if r["scene"] == scene]
        front = pareto(sr)
        for r in front:
            r["front"] = "yes"
        md.append("\n## %s\n\n" % scene)
        md.append(rl.md_table(sorted(sr, key=lambda r: (r["stable"] != "yes", r["pos_err_max_mm"])),
                              ["config", "eliminator", "force", "stable", "pos_err_max_mm", "gap_max_mm",
                               "depth_max_mm", "t_contact_us", "t_contact_range", "front", "why_unstable"],
                              ["method", "elim.", "force", "stable", "pos. error max (mm)", "gap max (mm)",
                               "depth max (mm)", "detect+elim (µs/step)", "range", "front", "why unstable"]))
        plot_pareto(a, scene, sr, front)
    rl.write_csv(os.path.join(a.results, "accuracy_time.csv"), rows, cols + ["front"])
    with open(os.path.join(a.results, "tables", "accuracy_time.md"), "w") as f:
        f.write("".join(md))
    fr = [dict(r, scene=r["scene"].replace("_", " ")) for r in rows if r["front"] == "yes"]
    with open(os.path.join(a.results, "tables", "accuracy_time_front.tex"), "w") as f:
        f.write(rl.tex_table(fr, ["scene", "config", "eliminator", "force", "pos_err_max_mm", "gap_max_mm",
                                  "t_contact_us", "t_contact_range"],
                             ["scenario", "method", "elim.", "force", "pos. err. (mm)", "gap (mm)",
                              "detect+elim ($\\mu$s)", "range (%d runs)" % a.repeats],
                             "Pareto front of error against time"))


DETECTOR_COLOUR = {"voxel": "#0072B2", "fcl": "#E69F00", "cgal": "#009E73", "hash": "#CC79A7", "bullet": "#D55E00"}
ELIMINATOR_MARKER = {"line": "o", "plane": "s", "projection": "^"}
# Errors above this (1 m) are runs that blew up: drawn at the top edge of the Pareto figures.
PARETO_CAP_MM = 1000.0


def plot_pareto(a, scene, rows, front):
    """Error against time, one marker per configuration (colour: detector, shape: eliminator,
    hollow: unstable); the front of the stable ones as a staircase with its points numbered
    1, 2, ... by time and named in the key beside the axes. Printed at the text width."""
    from matplotlib.lines import Line2D
    fig = plt.figure(figsize=(rl.TEXT, 2.9), layout="constrained")
    gs = fig.add_gridspec(1, 2, width_ratios=[1.3, 1.0])
    ax = fig.add_subplot(gs[0])
    key = fig.add_subplot(gs[1])
    key.axis("off")
    floor = 1e-3
    pts, off = [], 0
    shown = [r for r in rows if not (math.isnan(r["pos_err_max_mm"]) or math.isnan(r["t_contact_us"]))]

    def xy(r):
        return max(r["t_contact_us"], 0.1), min(max(r["pos_err_max_mm"], floor), PARETO_CAP_MM)
    for r in shown:
        x, y = xy(r)
        ok = r["stable"] == "yes"
        capped = r["pos_err_max_mm"] > PARETO_CAP_MM
        off += capped
        c = DETECTOR_COLOUR.get(r["detector"], "gray")
        ax.scatter(x, y, marker=ELIMINATOR_MARKER.get(r["eliminator"], "D"), s=26 if r in front else 14,
                   facecolor=c if ok else "none", edgecolor="k" if r in front else c, linewidth=0.7,
                   zorder=4 if r in front else 3, clip_on=False)
        if capped:
            ax.annotate("", xy=(x, y), xytext=(0, -9), textcoords="offset points", zorder=2,
                        arrowprops=dict(arrowstyle="->", lw=0.6, color=c, shrinkA=0, shrinkB=3))
        pts.append((x, y))
    fr = sorted(front, key=lambda r: (r["t_contact_us"], r["pos_err_max_mm"]))
    if fr:
        ax.step([xy(r)[0] for r in fr], [xy(r)[1] for r in fr], where="post", color="k", lw=0.7, zorder=2)
    ax.set_xscale("log")
    ax.set_yscale("log")
    rl.plain_log_ticks(ax.xaxis, ax.yaxis)
    if off:
        ax.set_ylim(top=2.0 * PARETO_CAP_MM)  # room above the blown-up runs, drawn at the cap
    ax.set_xlabel("detection + elimination (µs per step)")
    ax.set_ylabel("largest position error (mm)")
    ax.set_title(scene.replace("_", " "))
    ax.grid(True, which="major", alpha=0.35)
    ax.grid(True, which="minor", alpha=0.12)
    # Key: what the marks mean, then the front's points by number.
    # Two columns (the legend fills column by column): colours and hollow; shapes, front, off scale.
    col1 = [Line2D([], [], ls="none", marker="o", ms=5, mfc=DETECTOR_COLOUR.get(d, "gray"), mec="none", label=d)
            for d in sorted({r["detector"] for r in rows})]
    col1.append(Line2D([], [], ls="none", marker="o", ms=5, mfc="none", mec="0.3", label="unstable (hollow)"))
    col2 = [Line2D([], [], ls="none", marker=ELIMINATOR_MARKER[e], ms=5, mfc="0.5", mec="none", label=e)
            for e in ELIMINATOR_MARKER if any(r["eliminator"] == e for r in rows)]
    col2.append(Line2D([], [], color="k", lw=0.7, marker="o", ms=5, mfc="0.5", mec="k", label="front (stable)"))
    if off:
        col2.append(Line2D([], [], ls="none", marker="$\\uparrow$", ms=6, color="0.3",
                           label="%d above %g m (blown up)" % (off, PARETO_CAP_MM / 1e3)))
    n = max(len(col1), len(col2))
    blank = [Line2D([], [], ls="none", label=" ")]
    handles = col1 + blank * (n - len(col1)) + col2 + blank * (n - len(col2))
    leg = key.legend(handles=handles, loc="upper left", ncol=2, frameon=False, fontsize=rl.SMALL,
                     handletextpad=0.5, columnspacing=0.8, borderaxespad=0.0, title="marks", alignment="left",
                     title_fontproperties={"weight": "bold", "size": rl.SMALL})
    key.add_artist(leg)
    labels = ["%d" % (k + 1) for k in range(len(fr))]
    entries = [Line2D([], [], ls="none", label="%s  %s, %s, %s: %.3g mm, %s µs" % (
        labels[k], r["config"], r["eliminator"], r["force"], r["pos_err_max_mm"],
        ("%.0f" if r["t_contact_us"] >= 100 else "%.3g") % r["t_contact_us"])) for k, r in enumerate(fr)]
    if entries:
        key.legend(handles=entries, loc="lower left", frameon=False, fontsize=rl.SMALL, handlelength=0,
                   handletextpad=0, borderaxespad=0.0, title="front, by time", alignment="left",
                   title_fontproperties={"weight": "bold", "size": rl.SMALL})
    stair = [xy(fr[0])] if fr else []
    for r0, r1 in zip(fr[:-1], fr[1:]):
        stair += [(xy(r1)[0], xy(r0)[1]), xy(r1)]
    rl.place_labels(ax, [xy(r) for r in fr], labels, avoid=[p for p in pts if p not in [xy(r) for r in fr]],
                    lines=[stair])
    rl.save(fig, os.path.join(a.results, "figures", "pareto_%s" % scene), width=rl.TEXT)


# ---------------------------------------------------------------------------------------------
def ablation(a):
    rows, jobs, index = [], [], []
    for scene in SCENES:
        elim = PAPER_ELIMINATOR[scene]
        for v in ABLATION_VOXELS:
            for f in ABLATION_FORCES:
                js = repeated(a, scene, "ablation/%s/v%g_%s" % (scene, 1e3 * v, force_label(f)),
                              config_sets("voxel", v, elim, f, []), repeats=1)
                index.append((scene, v, f, len(jobs), len(js)))
                jobs += js
    base_at = len(jobs)
    for scene in SCENES:  # the baseline: contact measured, never pushed (force 0)
        jobs += repeated(a, scene, "ablation/%s/no_force" % scene,
                         config_sets("voxel", ABLATION_VOXELS[0], PAPER_ELIMINATOR[scene], "0", []), repeats=1)
    sums = run_all(a, jobs)
    baseline = {scene: figures(sums[base_at + k]) for k, scene in enumerate(SCENES)}
    for scene, v, f, i, n in index:
        rows.append(dict(combine(sums[i:i + n]), scene=scene, voxel_mm=1e3 * v, force=force_label(f),
                         eliminator=PAPER_ELIMINATOR[scene]))
    md = ["# Ablation: force rule and magnitude by voxel size (the voxel model)\n\n",
          "The paper's voxel model with its eliminator for the scenario; constant force F (N per contact), "
          "`auto`, and the depth penalty k (N/m), by voxel size. Errors against the reference (mm) and "
          "stability as in `accuracy_time.md`; time: the median step of one run (the accuracy study has the "
          "medians of several). Made by `scripts/study.py ablation`.\n"]
    reasons = ["% The voxel model's defaults chosen by the rule (made by scripts/study.py)\n"]
    chosen = {}
    for scene in SCENES:
        sr = [r for r in rows if r["scene"] == scene]
        best = chosen[scene] = choose(sr, baseline[scene])
        md.append("\n## %s (%s)\n\n" % (scene, PAPER_ELIMINATOR[scene]))
        md.append(rl.md_table(sr, ["voxel_mm", "force", "stable", "pos_err_max_mm", "gap_max_mm", "depth_max_mm",
                                   "contact_power_ratio", "t_contact_us", "why_unstable"],
                              ["voxel (mm)", "force", "stable", "pos. error max (mm)", "gap max (mm)",
                               "depth max (mm)", "contact work / energy in", "detect+elim (µs)", "why unstable"]))
        text = default_text(scene, sr, best, baseline[scene])
        md.append("\n" + text + "\n")
        reasons.append("\\paragraph{Default of \\code{%s}.} %s\n" % (rl.tex_escape(scene), rl.tex_escape(text)))
        plot_ablation(a, scene, sr)
    rl.write_csv(os.path.join(a.results, "ablation.csv"), rows,
                 ["scene", "eliminator", "voxel_mm", "force", "stable", "why_unstable", "settled", "pos_err_max_mm",
                  "gap_max_mm", "depth_max_mm", "contact_power_ratio", "stability", "t_contact_us", "t_contact_range", "recall",
                  "precision"])
    with open(os.path.join(a.results, "tables", "ablation.md"), "w") as f:
        f.write("".join(md))
    with open(os.path.join(a.results, "tables", "ablation_defaults.tex"), "w") as f:
        f.write("\n".join(reasons))
    with open(os.path.join(a.results, "defaults.json"), "w") as f:
        json.dump({scene: ({"voxel_size": chosen[scene]["voxel_mm"] / 1e3, "force": chosen[scene]["force"],
                            "eliminator": PAPER_ELIMINATOR[scene]} if chosen[scene] else None) for scene in SCENES},
                  f, indent=2, sort_keys=True)
        f.write("\n")


def default_text(scene, rows, best, base):
    stable = [r for r in rows if r["stable"] == "yes"]
    good = [r for r in stable if useful(r, base)]
    out = ("Rule: among the stable settings with a position error or a depth at most %g %% of the run without "
           "contact force (%.3g mm and %.3g mm here), the smallest largest position error; among those within 10 %% "
           "of it, the smallest gap; among those, the fastest. %d of %d settings are stable, %d of them clearly "
           "better than no force. " % (100 * USEFUL, base["pos_err_max_mm"], base["depth_max_mm"], len(stable),
                                       len(rows), len(good)))
    if best is None:
        return out + ("None qualifies: the voxel model has no default for this scenario, and CI has no accuracy "
                      "threshold for it (results/thresholds.json says why).")
    return out + ("Chosen: %s at %g mm voxels: position error %.3g mm, gap %.3g mm, depth %.3g mm, %.3g µs per "
                  "step for detection and elimination." % (best["force"], best["voxel_mm"], best["pos_err_max_mm"],
                                                            best["gap_max_mm"], best["depth_max_mm"],
                                                            best["t_contact_us"]))


def plot_ablation(a, scene, rows):
    """Two heat maps (position error, gap) by force rule and voxel size; the stable settings
    outlined. Printed at the text width."""
    forces = [force_label(f) for f in ABLATION_FORCES]
    voxels = [1e3 * v for v in ABLATION_VOXELS]
    panels = [("pos_err_max_mm", "largest position error (mm)"), ("gap_max_mm", "largest gap (mm)")]
    fig, axes = plt.subplots(1, 2, figsize=(rl.TEXT, 2.35), layout="constrained")
    for k, (ax, (key, title)) in enumerate(zip(axes, panels)):
        m = [[float("nan")] * len(forces) for _ in voxels]
        stable = []
        for r in rows:
            i, j = voxels.index(r["voxel_mm"]), forces.index(r["force"])
            m[i][j] = r[key]
            if r["stable"] == "yes":
                stable.append((j, i))
        im = rl.heatmap(ax, m, forces, ["%g" % v for v in voxels], title, stable, cap=PARETO_CAP_MM,
                        cap_text=">1 m")
        fig.colorbar(im, ax=ax, fraction=0.06, pad=0.02, aspect=15)
        ax.set_xlabel("force rule (F: constant, N; k: penalty, N/m)")
        if k == 0:
            ax.set_ylabel("voxel size (mm)")
    fig.suptitle("%s, %s eliminator; outlined: stable (%d of %d); >1 m: blown up" % (
        scene.replace("_", " "), PAPER_ELIMINATOR[scene], sum(r["stable"] == "yes" for r in rows), len(rows)))
    rl.save(fig, os.path.join(a.results, "figures", "ablation_%s" % scene), width=rl.TEXT)


# ---------------------------------------------------------------------------------------------
def defaults(a):
    path = os.path.join(a.results, "defaults.json")
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    return {}


def plot_convergence(a, rows):
    """Error, gap and depth against voxel size, one line per scenario (hollow markers: unstable).
    Printed at the text width."""
    from matplotlib.lines import Line2D
    fig = plt.figure(figsize=(rl.TEXT, 2.6), layout="constrained")
    gs = fig.add_gridspec(2, 3, height_ratios=[1.0, 0.2])
    axes = [fig.add_subplot(gs[0, k]) for k in range(3)]
    keyax = fig.add_subplot(gs[1, :])
    keyax.axis("off")
    for k, scene in enumerate(SCENES):
        sr = sorted((r for r in rows if r["scene"] == scene), key=lambda r: r["voxel_mm"])
        x = [r["voxel_mm"] for r in sr]
        c = rl.PALETTE[k]
        for ax, key in zip(axes, ["pos_err_max_mm", "gap_max_mm", "depth_max_mm"]):
            ax.plot(x, [r[key] for r in sr], "-", color=c, lw=1.0,
                    label="%s (%s)" % (scene.replace("_", " "), sr[0]["force"] if sr else ""))
            ax.scatter(x, [r[key] for r in sr], s=14, zorder=3, linewidth=0.8, edgecolor=c,
                       facecolor=[c if r["stable"] == "yes" else "white" for r in sr])
    for ax, t in zip(axes, ["largest position error (mm)", "largest gap (mm)", "deepest penetration (mm)"]):
        ax.set_xscale("log", base=2)
        ax.set_xticks(CONVERGENCE_VOXELS_MM)
        ax.set_xticklabels(["%g" % v for v in CONVERGENCE_VOXELS_MM])
        ax.minorticks_off()
        ax.set_xlabel("voxel size (mm)")
        ax.set_title(t)
        ax.grid(True, alpha=0.35)
    h, lab = axes[0].get_legend_handles_labels()
    h.append(Line2D([], [], ls="none", marker="o", ms=4, mfc="white", mec="0.3"))
    lab.append("unstable (hollow)")
    keyax.legend(h, lab, loc="center", ncol=2, frameon=False, borderaxespad=0.0, columnspacing=3.0)
    rl.save(fig, os.path.join(a.results, "figures", "convergence"), width=rl.TEXT)


def convergence(a):
    d = defaults(a)
    rows, jobs, index = [], [], []
    for scene in SCENES:
        force = d.get(scene) and d[scene]["force"]
        f = {"auto": "auto"}.get(force) or (json.dumps({"stiffness": float(force[2:])}) if force and force.startswith("k=")
                                            else force[2:] if force else PENALTY)
        for v in CONVERGENCE_VOXELS:
            js = [(scene, os.path.join(a.results, "sweeps", "convergence", scene, "v%g" % (1e3 * v)),
                   config_sets("voxel", v, PAPER_ELIMINATOR[scene], f, []))]
            index.append((scene, v, force_label(f), len(jobs)))
            jobs += js
    sums = run_all(a, jobs)
    for scene, v, f, i in index:
        rows.append(dict(figures(sums[i]), scene=scene, voxel_mm=1e3 * v, force=f))
    cols = ["scene", "voxel_mm", "force", "stable", "pos_err_max_mm", "pos_err_rms_mm", "gap_max_mm", "depth_max_mm",
            "t_contact_us", "why_unstable"]
    rl.write_csv(os.path.join(a.results, "convergence.csv"), rows, cols)
    plot_convergence(a, rows)
    with open(os.path.join(a.results, "tables", "convergence.md"), "w") as f:
        f.write("# Convergence as the grid refines\n\nThe voxel model with each scenario's default force rule "
                "(`defaults.json`) and its eliminator; voxel size halved from 32 to 2 mm. Errors against the "
                "reference, mm. Made by `scripts/study.py convergence`.\n\n" + rl.md_table(rows, cols, cols))


# ---------------------------------------------------------------------------------------------
# Mesh refinement: each scenario at its resolution and r times finer (the same physical time at
# dt / r, stable at the finer spacing).
def refine_sets(scene, r):
    s = rl.bundled_scene(scene)
    sets = []
    for i, b in enumerate(s["bodies"]):
        sh = b["shape"]
        if sh["type"] == "box":
            sets.append("bodies.%d.shape.cells=%s" % (i, json.dumps([c * r for c in sh["cells"]])))
        elif sh["type"] in ("sphere", "ellipsoid"):
            sets.append("bodies.%d.shape.subdivisions=%d" % (i, sh.get("subdivisions", 2) + int(math.log2(r))))
        elif sh["type"] == "cylinder":
            sets.append("bodies.%d.shape.segments=%d" % (i, sh.get("segments", 16) * r))
            sets.append("bodies.%d.shape.rings=%d" % (i, sh.get("rings", 4) * r))
    return sets


def refinement(a):
    factors = [1, 2] if not a.quick else [1]
    rows = []
    for scene in SCENES:
        for r in factors:
            out = os.path.join(a.results, "sweeps", "refinement", scene, "x%d" % r)
            summary = os.path.join(out, "summary.json")
            if not os.path.exists(summary):
                cmd = [a.harness, "run", scene, "--out", out, "--quiet", "--dt-divide", str(r), "--set",
                       "output.frames_every=0", "--set", 'references.solvers=["cgal"]']
                for s in refine_sets(scene, r) + a.extra_sets:
                    cmd += ["--set", s]
                subprocess.run(cmd, check=False, env=dict(os.environ, HARNESS_THREADS="1"), stderr=subprocess.DEVNULL)
            with open(summary) as f:
                s = json.load(f)
            disp = rl.largest_displacements(out)
            for body, d in disp.items():
                rows.append({"scene": scene, "resolution": "x%d" % r, "nodes": s["nodes"], "body": body,
                             "max_displacement_mm": 1e3 * d, "settled": s["settled"], "steps": s["steps_run"]})
    for row in rows:
        base = [x for x in rows if x["scene"] == row["scene"] and x["body"] == row["body"] and x["resolution"] == "x1"]
        row["vs_x1"] = row["max_displacement_mm"] / base[0]["max_displacement_mm"] if base and base[0][
            "max_displacement_mm"] > 0 else float("nan")
    cols = ["scene", "resolution", "nodes", "body", "max_displacement_mm", "vs_x1", "settled", "steps"]
    rl.write_csv(os.path.join(a.results, "refinement.csv"), rows, cols)
    text = ("# Mesh refinement\n\nEach scenario with its default contact at its resolution and twice as fine (box "
            "cells, cylinder segments and rings doubled, one more icosphere subdivision; dt halved, every step "
            "count doubled: the same physical time). Settled shape: the largest displacement of each body's "
            "surface from its rest position. sphere_collision and cylinder_press are driven by prescribed "
            "displacements: their largest displacement is set by the drivers, so agreement there checks the "
            "kinematics, not the material; implant_expansion (pressure and gravity against the tissue) is the "
            "material check. Four times as fine (256 times the work) is beyond the time budget. "
            "Made by `scripts/study.py refinement`.\n\n")
    with open(os.path.join(a.results, "tables", "refinement.md"), "w") as f:
        f.write(text + rl.md_table(rows, cols, ["scene", "resolution", "nodes", "body", "largest displacement (mm)",
                                                "over x1", "settled", "steps"]))
    with open(os.path.join(a.results, "tables", "refinement.tex"), "w") as f:
        f.write(rl.tex_table([dict(r, scene=r["scene"].replace("_", " ")) for r in rows],
                             ["scene", "resolution", "nodes", "body", "max_displacement_mm", "vs_x1"],
                             ["scenario", "mesh", "nodes", "body", "displacement (mm)", "over x1"],
                             "Settled shape against resolution"))


# ---------------------------------------------------------------------------------------------
# Real time, as a reviewer would accept it: per scene and method, the collision unit's time per
# step (detection + response, against a 1 ms haptic budget) and the whole simulator's, at the
# scene's dt, at 0.9 of the smallest dt_crit a run at the scene's dt met (the guard substeps if the
# state needs it: its substeps are counted in the step), and with implicit Euler at ten times the
# scene's dt; one and two threads; each with its error against the reference beside it. Every row
# carries the arguments that reproduce it with `harness run SCENE` (and the thread count).
HAPTIC_BUDGET_US = 1000.0
REALTIME_METHODS = [
    ("cgal both ways, penalty (scene default)", "exact", []),
    ("voxel_exact both ways, penalty", "completed", ['contacts.0.detector="voxel_exact"']),
    ("hash both ways, penalty", "exact", ['contacts.0.detector="hash"']),
    ("voxel 4 mm line auto (the paper's)", "paper",
     ['contacts.0.detector="voxel"', 'contacts.0.eliminator="line"', 'contacts.0.force="auto"', "contacts.0.two_sided=false",
      "contacts.0.voxel_size=0.004"]),
]


def shell_args(args):
    """The arguments as one shell-quoted string."""
    import shlex
    return " ".join(shlex.quote(x) for x in args)


def realtime_run(a, scene, folder, args, threads, compare):
    """A `harness run SCENE ARGS` (its summary), with the references measuring for the error when
    compare (timings exclude measurement: summary timing_us are the step's own)."""
    out = os.path.join(a.results, "sweeps", "realtime", folder)
    summary = os.path.join(out, "summary.json")
    if not os.path.exists(summary):
        cmd = [a.harness, "run", scene, "--out", out, "--quiet", "--set", "output.frames_every=0"] + args
        if compare:
            cmd += ["--set", 'references.solvers=["cgal"]', "--set", "references.every=%d" % STUDY_EVERY,
                    "--compare", os.path.join(a.results, "references", scene)]
        else:
            cmd += ["--set", "references.solvers=[]"]
        if a.quick:
            cmd += ["--set", "time.steps=300", "--set", "time.settle.max_steps=400"]
        subprocess.run(cmd, check=False, env=dict(os.environ, HARNESS_THREADS=str(threads)), stderr=subprocess.DEVNULL)
    with open(summary) as f:
        return json.load(f)


def realtime(a):
    rows = []
    for scene in SCENES:
        dt0 = rl.bundled_scene(scene)["time"]["dt"]
        for label, kind, sets in REALTIME_METHODS:
            base = sum((["--set", x] for x in sets), [])
            tag = label.split(" (")[0].replace(" ", "_").replace(",", "")
            # The scene's dt first: its smallest dt_crit sets the dt of the second mode.
            first = realtime_run(a, scene, "%s/%s_scene_t1" % (scene, tag), base, 1, True)
            dt_crit_min = num((first.get("stability") or {}).get("dt_crit_min"))
            modes = [("scene dt", base)]
            if dt_crit_min > 0:
                modes.append(("0.9 dt_crit", base + ["--dt", "%.4g" % (0.9 * dt_crit_min), "--set", 'time.guard="substep"']))
            modes.append(("implicit Euler, 10 dt", base + ["--dt", "%.4g" % (10 * dt0), "--set",
                                                           'time.integrator="implicit_euler"']))
            for mode, args in modes:
                for threads in [1, 2]:
                    folder = "%s/%s_%s_t%d" % (scene, tag, mode.split(",")[0].replace(" ", "_").replace(".", ""), threads)
                    s = first if (mode == "scene dt" and threads == 1) else realtime_run(a, scene, folder, args, threads, threads == 1)
                    t = s.get("timing_us") or {}
                    st = s.get("stability") or {}
                    dt = num(st.get("dt"))
                    step_us, contact_us = num(t.get("step")), num(t.get("detect"), 0.0) + num(t.get("eliminate"), 0.0)
                    f = figures(s) if threads == 1 else {}
                    rows.append({"scene": scene, "method": label, "kind": kind, "mode": mode, "threads": threads,
                                 "dt": dt, "integrator": st.get("integrator"), "substeps_max": st.get("max_substeps"),
                                 "overrides": shell_args(args), "t_step_us": step_us, "t_contact_us": contact_us,
                                 "contact_budget_share": contact_us / HAPTIC_BUDGET_US,
                                 "realtime_factor": dt * 1e6 / step_us if step_us > 0 else float("nan"),
                                 "pos_err_max_mm": f.get("pos_err_max_mm", float("nan")), "stability": f.get("stability", ""),
                                 "status": s.get("status"), "steps": s.get("steps_run")})
        # The best exact method's error at the scene's dt: every row's error against it.
        exact = [r["pos_err_max_mm"] for r in rows if r["scene"] == scene and r["kind"] == "exact"
                 and r["mode"] == "scene dt" and r["threads"] == 1 and not math.isnan(r["pos_err_max_mm"])]
        best = min(exact) if exact else float("nan")
        for r in rows:
            if r["scene"] == scene:
                r["best_exact_mm"] = best
                r["error_over_best"] = r["pos_err_max_mm"] / best if best > 0 else float("nan")
        # Errors of the two-thread rows: the same state as one thread (bit-identical): copied.
        for r in rows:
            if r["scene"] == scene and r["threads"] == 2:
                twin = next(o for o in rows if o["scene"] == scene and o["method"] == r["method"] and o["mode"] == r["mode"]
                            and o["threads"] == 1)
                r["pos_err_max_mm"], r["stability"], r["error_over_best"] = (twin["pos_err_max_mm"], twin["stability"],
                                                                              twin["error_over_best"])
    cols = ["scene", "method", "kind", "mode", "threads", "dt", "integrator", "substeps_max", "t_step_us", "t_contact_us",
            "contact_budget_share", "realtime_factor", "pos_err_max_mm", "best_exact_mm", "error_over_best", "stability",
            "status", "steps", "overrides"]
    rl.write_csv(os.path.join(a.results, "realtime.csv"), rows, cols)
    heads = ["scene", "method", "kind", "mode", "threads", "dt (s)", "integrator", "substeps", "step (µs)",
             "detect+response (µs)", "of 1 ms", "real-time factor", "pos. error (mm)", "best exact (mm)", "error / best",
             "stability", "status", "steps", "arguments after `harness run SCENE`"]
    with open(os.path.join(a.results, "tables", "realtime.md"), "w") as f:
        f.write("# Real time\n\nPer scene and method: the collision unit's time per step (detection + response, "
                "median over the run's steps, against a 1 ms haptic budget) and the whole step's (the simulator's: "
                "real-time factor = simulated time per wall time = dt / median step), at the scene's dt, at 0.9 of "
                "the smallest dt_crit the run at the scene's dt met (guard `substep` as a safety net: its substeps are "
                "inside the step's time), and with implicit Euler at ten times the scene's dt; one and two threads "
                "(HARNESS_THREADS); the error against the reference over the final window beside it (the same "
                "state with two threads), and its ratio to the best exact method's at the scene's dt. Timings "
                "exclude the references' measurement. `overrides`: the arguments after `harness run SCENE` that "
                "reproduce the row. Made by `scripts/study.py realtime`; the machine is shared: timings vary.\n\n"
                + rl.md_table(rows, cols, heads))
    with open(os.path.join(a.results, "tables", "realtime.tex"), "w") as f:
        tcols = ["scene", "method", "mode", "threads", "t_step_us", "t_contact_us", "realtime_factor", "error_over_best"]
        f.write(rl.tex_table([dict(r, scene=r["scene"].replace("_", " ")) for r in rows], tcols,
                             ["scene", "method", "mode", "threads", "step ($\\mu$s)", "collision ($\\mu$s)",
                              "real-time factor", "error / best exact"], "Real time"))


STUDIES = ["references", "accuracy", "ablation", "convergence", "refinement", "realtime", "swap", "region", "orient",
           "bullet"]


# ---------------------------------------------------------------------------------------------
# Which body carries the grid (the paper leaves it open): host and guest swapped.
SWAP_BODIES = {"sphere_collision": ("left", "right"), "cylinder_press": ("layer", "cylinder"),
               "implant_expansion": ("implant", "tissue")}
SCENE_VOXEL = {"sphere_collision": 0.004, "cylinder_press": 0.004, "implant_expansion": 0.008}


def swap_configs(a, scene):
    """The voxel model's default of the scene (defaults.json) when there is one, and the paper's
    eliminator with the automatic force at the scene's voxel size."""
    out = [(PAPER_ELIMINATOR[scene], "auto", SCENE_VOXEL[scene])]
    path = os.path.join(a.results, "defaults.json")
    d = json.load(open(path)).get(scene) if os.path.exists(path) else None
    if d:
        f = d["force"]
        force = "auto" if f == "auto" else (f[2:] if f.startswith("F=") else json.dumps({"stiffness": float(f[2:])}))
        cfg = (d["eliminator"], force, d["voxel_size"])
        if cfg not in out:
            out.insert(0, cfg)
    return out


def swap(a):
    rows, configs = [], []
    for scene in SCENES:
        host, guest = SWAP_BODIES[scene]
        for elim, force, voxel in swap_configs(a, scene):
            for swapped in (False, True):
                h, g = (guest, host) if swapped else (host, guest)
                sets = config_sets("voxel", voxel, elim, force, ['contacts.0.host="%s"' % h, 'contacts.0.guest="%s"' % g,
                                                                 "references.every=%d" % STUDY_EVERY])
                folder = "swap/%s/%s_%s_%g_%s" % (scene, elim, force_label(force), 1e3 * voxel, "swapped" if swapped else "as_scene")
                configs.append(((scene, elim, force, voxel, h, g, swapped), scene, folder, sets))
    for (scene, elim, force, voxel, h, g, swapped), s in run_configs(a, configs):
        p = s["pairs"][0] if s.get("pairs") else {}
        rows.append(dict(figures(s), scene=scene, eliminator=elim, force=force_label(force), voxel_mm=1e3 * voxel,
                         host=h, guest=g, swapped="yes" if swapped else "no", max_depth_peak_mm=1e3 * num(p.get("max_depth_peak"))))
    cols = ["scene", "eliminator", "force", "voxel_mm", "host", "guest", "swapped", "stable", "why_unstable",
            "pos_err_max_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "recall",
            "precision", "t_contact_us"]
    rl.write_csv(os.path.join(a.results, "swap.csv"), rows, cols)
    md = ["# Which body carries the grid\n\n",
          "The voxel model with host and guest as the scene has them and swapped (the grid on the other body), "
          "against the converged reference (errors at the end of the run, mm; peak depth over the run; recall "
          "and precision of the guest nodes detected, CGAL every 10 steps). Made by `scripts/study.py swap`.\n\n",
          rl.md_table(rows, ["scene", "eliminator", "force", "voxel_mm", "host", "guest", "stable", "pos_err_max_mm",
                             "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "recall",
                             "t_contact_us"],
                      ["scene", "elim.", "force", "voxel (mm)", "host (grid)", "guest", "stable", "pos. error (mm)",
                       "gap (mm)", "depth (mm)", "peak depth (mm)", "pen. final", "recall", "detect+elim (µs)"])]
    with open(os.path.join(a.results, "tables", "swap.md"), "w") as f:
        f.write("".join(md))


# ---------------------------------------------------------------------------------------------
# Claim (e): "if voxels are built for large space area near penetrating bodies then collisions are
# detected for any deformations": the region (half, full, overlap) and its margin under the two
# scenes whose bodies deform most (the implant expanding under the tissue, the cylinder pressed in).
REGION_SCENES = ["implant_expansion", "cylinder_press"]
REGIONS = ["half", "full", "overlap"]
MARGINS = [0, 1, 3]


def region(a):
    rows, configs = [], []
    for scene in REGION_SCENES:
        for reg in REGIONS:
            for m in MARGINS:
                sets = config_sets("voxel", SCENE_VOXEL[scene], PAPER_ELIMINATOR[scene], "auto",
                                   ['contacts.0.region="%s"' % reg, "contacts.0.margin=%d" % m])
                configs.append(((scene, reg, m), scene, "region/%s/%s_margin%d" % (scene, reg, m), sets))
    for (scene, reg, m), s in run_configs(a, configs):
        p = s["pairs"][0] if s.get("pairs") else {}
        rows.append(dict(figures(s), scene=scene, region=reg, margin=m,
                         region_rebuilds=num(p.get("region_rebuilds")),
                         max_depth_peak_mm=1e3 * num(p.get("max_depth_peak"))))
    cols = ["scene", "region", "margin", "stable", "why_unstable", "pos_err_max_mm", "gap_max_mm", "depth_max_mm",
            "max_depth_peak_mm", "true_pen_final", "recall", "precision", "region_rebuilds", "t_contact_us"]
    rl.write_csv(os.path.join(a.results, "region.csv"), rows, cols)
    md = ["# Claim (e): the region of the grid under large deformation\n\n",
          "The voxel model (the paper's eliminator, automatic force, the scene's voxel size) with the grid over half "
          "of the host's box facing the guest, the whole box, or the overlap of the two boxes, and 0, 1 or 3 voxels "
          "of margin. Recall: guest nodes detected among those truly penetrating (CGAL every 10 steps, over the run). "
          "Made by `scripts/study.py region`.\n\n",
          rl.md_table(rows, ["scene", "region", "margin", "stable", "pos_err_max_mm", "depth_max_mm",
                             "max_depth_peak_mm", "true_pen_final", "recall", "region_rebuilds", "t_contact_us"],
                      ["scene", "region", "margin (voxels)", "stable", "pos. error (mm)", "depth (mm)",
                       "peak depth (mm)", "pen. final", "recall", "rebuilds", "detect+elim (µs)"])]
    with open(os.path.join(a.results, "tables", "region.md"), "w") as f:
        f.write("".join(md))


# ---------------------------------------------------------------------------------------------
# Claim (a) without its confound: the paper's line points from the host node to the guest node,
# its plane agrees with the host's outward normals; `orient` makes both the same either way, over
# the force x voxel grid of the voxel model on the implant (the claim's scene).
ORIENT_SCENE = "implant_expansion"
ORIENT_FORCES = ["0.003", "0.03", "auto"]
ORIENT_VOXELS = [0.004, 0.008, 0.016]


def orient(a):
    rows, configs = [], []
    for force in ORIENT_FORCES:
        for voxel in ORIENT_VOXELS:
            for elim in ["line", "plane"]:
                for o in ["guest", "outward"]:
                    sets = config_sets("voxel", voxel, elim, force, ['contacts.0.orient="%s"' % o])
                    folder = "orient/%s/%s_%s_%g_%s" % (ORIENT_SCENE, elim, force_label(force), 1e3 * voxel, o)
                    configs.append(((force, voxel, elim, o), ORIENT_SCENE, folder, sets))
    for (force, voxel, elim, o), s in run_configs(a, configs):
        p = s["pairs"][0] if s.get("pairs") else {}
        rows.append(dict(figures(s), scene=ORIENT_SCENE, eliminator=elim, orient=o, force=force_label(force),
                         voxel_mm=1e3 * voxel, max_depth_peak_mm=1e3 * num(p.get("max_depth_peak"))))
    cols = ["scene", "eliminator", "orient", "force", "voxel_mm", "stable", "why_unstable", "pos_err_max_mm",
            "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "recall", "t_contact_us"]
    rl.write_csv(os.path.join(a.results, "orient.csv"), rows, cols)
    md = ["# Claim (a) without its confound: line and plane, each oriented both ways\n\n",
          "The voxel model on %s: line and plane with `orient` `guest` (pushed from the host node, or the plane, "
          "toward the guest node: the paper's line) and `outward` (agreeing with the host's outward normals: the "
          "paper's plane), over forces %s and voxels %s mm, against the converged reference (errors at the end, mm). "
          "Made by `scripts/study.py orient`; the verdict is in claims.md.\n\n" % (
              ORIENT_SCENE, ", ".join(force_label(f) for f in ORIENT_FORCES), ", ".join("%g" % (1e3 * v) for v in ORIENT_VOXELS)),
          rl.md_table(rows, ["force", "voxel_mm", "eliminator", "orient", "stable", "pos_err_max_mm", "gap_max_mm",
                             "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "t_contact_us", "why_unstable"],
                      ["force", "voxel (mm)", "elim.", "orient", "stable", "pos. error (mm)", "gap (mm)", "depth (mm)",
                       "peak depth (mm)", "pen. final", "detect+elim (µs)", "why unstable"])]
    with open(os.path.join(a.results, "tables", "orient.md"), "w") as f:
        f.write("".join(md))


# ---------------------------------------------------------------------------------------------
# The peer engine: Bullet's soft bodies (`--engine bullet`) on the variants of the scenes that Bullet
# can represent (experiments/scenes/bullet/: linear springs, no dashpot), against the converged
# reference of the same variant, beside three of the harness's methods on the same variant.
BULLET_SCENES = ["sphere_collision", "cylinder_press"]
BULLET_CONFIGS = [
    ("Bullet, margin auto", ["--engine", "bullet"], []),
    ("Bullet, margin auto, 4 iterations", ["--engine", "bullet", "--bullet-iterations", "4"], []),
    ("Bullet, margin 0.05 mm", ["--engine", "bullet", "--bullet-margin", "5e-5"], []),
    ("Bullet, margin 0.5 mm", ["--engine", "bullet", "--bullet-margin", "5e-4"], []),
    ("harness cgal both ways k=500 (scene)", [], []),
    ("harness hash line auto", [], config_sets("hash", None, "line", "auto", [])),
    ("harness voxel 4 mm line auto", [], config_sets("voxel", 0.004, "line", "auto", [])),
]


def bullet_reference(a, scene):
    """The variant's reference: results/references/bullet_<scene>, made here when missing."""
    dest = os.path.join(a.results, "references", "bullet_" + scene)
    if not os.path.exists(os.path.join(dest, "surfaces.csv")):
        work = os.path.join(a.results, "sweeps", "references", "bullet_" + scene)
        cmd = [a.harness, "reference", "bullet/" + scene, "--out", work, "--quiet"]
        if a.quick:
            cmd += ["--max-levels", "2", "--set", "time.steps=300", "--set", "time.settle.max_steps=400"]
        subprocess.run(cmd, check=True, env=dict(os.environ, HARNESS_THREADS="1"))
        os.makedirs(dest, exist_ok=True)
        for f in ["summary.json", "surfaces.csv"]:
            shutil.copy(os.path.join(work, f), os.path.join(dest, f))
    return dest


def bullet_run(a, scene, out, args, sets, ref):
    summary = os.path.join(out, "summary.json")
    if not os.path.exists(summary):
        cmd = [a.harness, "run", "bullet/" + scene, "--out", out, "--quiet", "--compare", ref, "--set",
               "output.frames_every=0"] + (["--set", "time.settle.max_steps=400"] if a.quick else []) + [
               "--set", "references.every=%d" % STUDY_EVERY] + args
        for x in sets + a.extra_sets:
            cmd += ["--set", x]
        subprocess.run(cmd, check=False, env=dict(os.environ, HARNESS_THREADS="1"), stderr=subprocess.DEVNULL)
    with open(summary) as f:
        return json.load(f)


def bullet(a):
    jobs = []
    for scene in BULLET_SCENES:
        ref = bullet_reference(a, scene)
        for label, args, sets in BULLET_CONFIGS:
            out = os.path.join(a.results, "sweeps", "bullet", scene, label.replace(" ", "_").replace(",", "").replace("(", "").replace(")", ""))
            jobs.append((scene, label, out, args, sets, ref))
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        sums = list(ex.map(lambda j: bullet_run(a, j[0], j[2], j[3], j[4], j[5]), jobs))
    rows = []
    for (scene, label, out, args, sets, ref), s in zip(jobs, sums):
        p = s["pairs"][0] if s.get("pairs") else {}
        e = s.get("engine") or {}
        with open(os.path.join(ref, "summary.json")) as f:
            rs = json.load(f)
        conv = (rs.get("reference") or {}).get("converged", "")
        f = figures(s)
        if e.get("name") == "bullet":  # no work booked: stable = finite (figures() reads the audit as closed)
            f["stable"] = "yes" if s.get("status") == "ok" else "no"
        rows.append(dict(f, scene=scene, config=label, engine=e.get("name", "harness"),
                         margin_mm=1e3 * max(e.get("margin_m") or [float("nan")]),
                         residual=num(s.get("residual")), kinetic_energy_final=num(s.get("kinetic_energy_final")),
                         max_depth_peak_mm=1e3 * num(p.get("max_depth_peak")),
                         reference_converged="yes" if conv is True else "no"))
    cols = ["scene", "config", "engine", "margin_mm", "stable", "settled", "steps", "residual", "kinetic_energy_final",
            "pos_err_max_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "t_contact_us",
            "t_step_us", "reference_converged"]
    rl.write_csv(os.path.join(a.results, "bullet.csv"), rows, cols)
    md = ["# The peer engine: Bullet's soft bodies\n\n",
          "`harness run bullet/SCENE --engine bullet` (Bullet %s, reference/bullet_engine.hpp: the same nodes, "
          "masses, pins and drivers, links of the same rest lengths with kLST = k dt^2 (1/m_a + 1/m_b) / iterations, "
          "velocity damping kDP = mass_damping x dt, vertex-face soft-soft contact VF_SS with the margin shown) beside "
          "three of the harness's methods, on the variants Bullet can represent (experiments/scenes/bullet/: linear "
          "springs, no dashpot), against the reference solution of the same variant. Errors over the final "
          "window (mm, as in accuracy_time.md); residual: the force residual at the end (settled: below the "
          "scene's tolerance, %s, for 100 steps); t_contact: detection (and for the harness elimination) per step, µs, median; t_step: the "
          "whole step. Bullet's contact response is solved inside its position solver with the links: its "
          "t_contact is its collision pass alone. Made by `scripts/study.py bullet`.\n\n" % (
              (next((s.get("versions", {}).get("Bullet") for s in sums if s.get("versions", {}).get("Bullet")), "?")),
              "1e-5"),
          rl.md_table(rows, ["scene", "config", "margin_mm", "stable", "settled", "residual", "pos_err_max_mm",
                             "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "t_contact_us",
                             "t_step_us", "reference_converged"],
                      ["scene", "method", "margin (mm)", "stable", "settled", "residual", "pos. error (mm)",
                       "gap (mm)", "depth (mm)", "peak depth (mm)", "pen. final", "contact (µs)", "step (µs)",
                       "reference converged"])]
    with open(os.path.join(a.results, "tables", "bullet.md"), "w") as f:
        f.write("".join(md))
    with open(os.path.join(a.results, "tables", "bullet.tex"), "w") as f:
        f.write(rl.tex_table(rows, ["scene", "config", "margin_mm", "settled", "residual", "pos_err_max_mm", "gap_max_mm",
                                    "depth_max_mm", "true_pen_final", "t_contact_us", "t_step_us"],
                             ["scenario", "method", "margin (mm)", "settled", "residual", "pos.\\ err. (mm)",
                              "gap (mm)", "depth (mm)", "pen.", "contact ($\\mu$s)", "step ($\\mu$s)"],
                             "Bullet against the harness on the Bullet variants"))


# ---------------------------------------------------------------------------------------------
# --plots-only: the figures again from the committed CSVs (nothing is run).
def read_rows(path):
    """A study's CSV as rows: numbers as floats (nan when empty), the rest as text."""
    text = {"scene", "config", "detector", "eliminator", "force", "stable", "why_unstable", "settled",
            "t_contact_range", "front"}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [{k: (v if k in text else num(v)) for k, v in r.items()} for r in rows]


def plots_accuracy(a):
    rows = read_rows(os.path.join(a.results, "accuracy_time.csv"))
    for scene in SCENES:
        sr = [r for r in rows if r["scene"] == scene]
        plot_pareto(a, scene, sr, [r for r in sr if r["front"] == "yes"])


def plots_ablation(a):
    rows = read_rows(os.path.join(a.results, "ablation.csv"))
    for scene in SCENES:
        plot_ablation(a, scene, [r for r in rows if r["scene"] == scene])


def plots_convergence(a):
    plot_convergence(a, read_rows(os.path.join(a.results, "convergence.csv")))


PLOTS = {"accuracy": plots_accuracy, "ablation": plots_ablation, "convergence": plots_convergence}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", nargs="+", choices=STUDIES + ["all"])
    ap.add_argument("--harness", default="build/bin/harness")
    ap.add_argument("--results", default="results")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("-j", dest="jobs", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--plots-only", action="store_true",
                    help="only redraw the figures of the named studies from their CSVs in --results "
                         "(accuracy_time.csv, ablation.csv, convergence.csv); runs nothing")
    a = ap.parse_args()
    a.extra_sets = ["time.steps=300"] if a.quick else []
    if a.quick:
        a.repeats = 1
    for d in ["figures", "tables"]:
        os.makedirs(os.path.join(a.results, d), exist_ok=True)
    for w in (STUDIES if "all" in a.what else a.what):
        if a.plots_only:
            if w in PLOTS:
                print("study: %s figures from the CSV" % w, file=sys.stderr)
                PLOTS[w](a)
            continue
        print("study:", w, file=sys.stderr)
        globals()[w](a)
    if not a.plots_only:
        counts.write(a.results)  # the report's counts follow the results


if __name__ == "__main__":
    main()
