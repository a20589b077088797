"""study.py card: one scene's verdict at a glance (docs/tutorial.md). The scene's contact run with
each detector (its own eliminator and force), beside the same scene with no contact force, every
run compared with the scene's converged reference and judged as the studies judge (rules.py):
error over the final window, chatter, stability class, tunnelling, "helps" (rules.useful against
the no-force run), time per step (mean and 99th percentile of steps.csv's t_step_us: one run at a
time, one thread). Writes OUT/card.md, OUT/card.csv, OUT/card.{png,pdf}; the runs are a
`harness sweep --baseline` in OUT/runs/ (cached: delete it to rerun), the reference (when none is
given) a `harness reference` in OUT/reference/.
"""

import math
import os
import subprocess

from . import reader, rules, style, writers
from .reader import scene_name

METHODS = ["voxel", "voxel_exact", "cgal"]
EVERY = 10  # CGAL measures every run every EVERY steps, as in every study (studies/common.py STUDY_EVERY)


def find_reference(a, scene, out):
    """The reference to judge against: --reference, else results/references/<name> for a bundled
    scene, else `harness reference SCENE` made now into OUT/reference/."""
    if a.reference:
        return a.reference
    bundled = os.path.join(a.results, "references", scene_name(scene))
    if not os.path.isfile(scene) and reader.has_summary(bundled):
        return bundled
    ref = os.path.join(out, "reference")
    if not reader.has_summary(ref):
        print("card: making the reference of %s into %s (harness reference)" % (scene, ref))
        subprocess.run([a.harness, "reference", scene, "--out", ref, "--quiet"] +
                       sum((["--set", s] for s in a.card_sets), []), check=True)
    return ref


def sweep(a, scene, out, ref):
    """The runs: `harness sweep --baseline` over the detectors, compared with the reference, one at a
    time on one thread (their times are read)."""
    runs = os.path.join(out, "runs")
    folders = ["contacts.0.detector-%s" % m for m in a.methods] + ["no_force"]
    # Cached only where every run's steps.csv and timing.csv are there (a clone holds the summaries
    # alone).
    if not all(reader.stored(os.path.join(runs, f, n)) for f in folders for n in ("steps.csv", "timing.csv")):
        sets = ["output.frames_every=0", 'references.solvers=["cgal"]', "references.every=%d" % EVERY] + a.card_sets
        cmd = [a.harness, "sweep", scene, "--grid", "contacts.0.detector=" + ",".join(a.methods), "--baseline",
               "--compare", ref, "--out", runs, "-j", "1"] + sum((["--set", s] for s in sets), [])
        subprocess.run(cmd, check=True, env=dict(os.environ, HARNESS_THREADS="1"))
    return runs


def step_times(folder):
    """(mean, p99, max) of the run's per-step times, us (the first pair's rows of steps.csv)."""
    cols = reader.load_steps(folder)
    first = cols["pair"][0] if cols.get("pair") else None
    t = sorted(v for v, p in zip(cols["t_step_us"], cols.get("pair", [first] * len(cols["t_step_us"])))
               if p == first and reader.present(v))
    if not t:
        return math.nan, math.nan, math.nan
    return sum(t) / len(t), t[min(len(t) - 1, int(math.ceil(0.99 * len(t))) - 1)], t[-1]


def row(folder, method):
    s = reader.load_summary(folder)
    f = dict(reader.window_figures(s), **rules.stability_fields(s))
    mean, p99, mx = step_times(folder)
    return dict(f, method=method, folder=os.path.basename(folder), t_mean_us=mean, t_p99_us=p99, t_max_us=mx,
                tunnelled_total=reader.tunnelled_both(s))


def judge(rows, base, floor_mm=0.0):
    """Each row's helps / useless words, and the one-sentence verdict: the closest of the stable
    methods that help, or those within the noise of it (rules.noise: 10 %, the two chatters, the
    reference's floor `floor_mm`) with the fastest of them named."""
    for r in rows:
        r["helps"] = "yes" if rules.useful(r, base) else "no"
        r["useless"] = rules.useless_text(dict(r, tunnelled=r["tunnelled_total"]))  # both bodies' nodes
    good = [r for r in rows if r["stable"] == "yes" and not r["useless"]]
    if not good:
        return no_good_sentence(rows, base, floor_mm)
    best = min(good, key=lambda r: r["pos_err_max_mm"])
    tied = [r for r in good if r["pos_err_max_mm"] <= best["pos_err_max_mm"] + rules.noise(best, r, floor=floor_mm)]
    if len(tied) > 1:
        fast = min(tied, key=lambda r: r["t_mean_us"])
        return ("%s are the closest to the reference among the stable methods that help, within the noise of each "
                "other (%.3g to %.3g mm; no force: %.3g mm); the fastest of them is %s: %.0f us per step (p99 %.0f)."
                % (", ".join(r["method"] for r in tied), best["pos_err_max_mm"],
                   max(r["pos_err_max_mm"] for r in tied), base["pos_err_max_mm"], fast["method"], fast["t_mean_us"],
                   fast["t_p99_us"]))
    fast = min(good, key=lambda r: r["t_mean_us"])
    out = ("%s is the closest to the reference among the stable methods that help: %.3g mm (no force: %.3g mm), "
           "%.0f us per step (p99 %.0f)." % (best["method"], best["pos_err_max_mm"], base["pos_err_max_mm"],
                                              best["t_mean_us"], best["t_p99_us"]))
    if fast is not best:
        out += " The fastest of them is %s: %.3g mm at %.0f us." % (fast["method"], fast["pos_err_max_mm"], fast["t_mean_us"])
    return out


def no_good_sentence(rows, base, floor_mm):
    """The verdict where no method is stable, helps and keeps every node out: the closest run and every
    run within the noise of it (rules.noise), each with what it is."""
    measured = [r for r in rows if not math.isnan(r["pos_err_max_mm"])]
    head = ("No method is stable, helps and keeps every node out here: the no-force run ends %.3g mm from the "
            "reference" % base["pos_err_max_mm"])
    if not measured:
        return head + ", and no run has an error."
    best = min(measured, key=lambda r: r["pos_err_max_mm"])
    tied = [r for r in measured if r["pos_err_max_mm"] <= best["pos_err_max_mm"] + rules.noise(best, r, floor=floor_mm)]
    if len(tied) == 1:
        return head + ", and the closest run (%s, %.3g mm) is %s." % (best["method"], best["pos_err_max_mm"],
                                                                    describe(best))
    return head + (", and the closest runs, within the noise of each other (%.3g to %.3g mm), are %s." % (
        best["pos_err_max_mm"], max(r["pos_err_max_mm"] for r in tied),
        "; ".join("%s, %s" % (r["method"], describe(r)) for r in tied)))


def describe(r):
    if r["stable"] != "yes":
        return "%s (%s)" % (r["stability"], r["why_unstable"] or "not stable")
    return "stable but %s" % (r["useless"] or "fine")


COLUMNS = ["method", "pos_err_max_mm", "pos_err_amp_mm", "depth_max_mm", "stability", "tunnelled_total", "helps",
           "useless", "t_mean_us", "t_p99_us", "t_max_us", "why_unstable", "folder"]
HEADS = ["method", "error (mm)", "chatter (mm)", "depth (mm)", "stability", "tunnelled", "helps", "useless",
         "step mean (µs)", "step p99 (µs)", "step max (µs)", "why unstable", "run"]


def write(out, name, ref, rows, base, sentence):
    floor_m, floor_rule = reader.reference_floor(reader.load_summary(ref))
    conv = reader.reference_converged(reader.load_summary(ref))
    if not conv:
        sentence = ("Judged against a reference that did not converge (floor %.3g mm: differences below it are not "
                    "told apart): " % (1e3 * floor_m)) + sentence
    # The no-force run still detects (its force is 0): its time is not a method's, and is not shown.
    all_rows = rows + [dict(base, method="no contact force", helps="", useless="", t_mean_us="", t_p99_us="", t_max_us="")]
    writers.write_csv(os.path.join(out, "card.csv"), all_rows, COLUMNS)
    md = ["# %s: the verdict card\n\n" % name, sentence + "\n\n",
          writers.md_table(all_rows, COLUMNS, HEADS),
          "\nError: the largest node distance from the reference's settled surfaces, mean over the final window "
          "(chatter: its max - min there); depth: the deepest true penetration (CGAL) in the window. Reference: `%s`, "
          "%s, floor %.3g mm (%s): errors closer than that are not told apart. Stability and \"helps\" by the studies' "
          "rules (`scripts/study.py --help`); times from one run at a time on one thread, measurement excluded (the "
          "run with no contact force still detects: no time is given for it). "
          "Runs: `%s`. Made by `scripts/study.py card`.\n" % (
              ref, "converged" if conv else "NOT converged", 1e3 * floor_m, floor_rule, os.path.join(out, "runs"))]
    writers.write_text(os.path.join(out, "card.md"), "".join(md))
    plot(out, name, rows, base, 1e3 * floor_m)


def plot(out, name, rows, base, floor_mm):
    plt = style.pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(style.TEXT, 0.5 + 0.3 * len(rows)), layout="constrained", sharey=True)
    ys = list(range(len(rows)))
    colour = ["C2" if r["stable"] == "yes" and not r["useless"] else "0.6" for r in rows]
    ax1.barh(ys, [min(r["pos_err_max_mm"], 1e3) for r in rows], color=colour,
             xerr=[[0] * len(rows), [r["pos_err_amp_mm"] if r["pos_err_amp_mm"] == r["pos_err_amp_mm"] else 0 for r in rows]])
    ax1.axvline(base["pos_err_max_mm"], color="C3", ls="--", label="no contact force")
    if floor_mm == floor_mm:
        ax1.axvspan(0, floor_mm, color="0.85", label="reference floor")
    ax1.set_yticks(ys, [r["method"] for r in rows])
    ax1.set_xlabel("error over the window (mm; whisker: chatter)")
    ax1.legend(loc="best", fontsize=style.SMALL)
    ax2.barh(ys, [r["t_mean_us"] for r in rows], color=colour)
    ax2.plot([r["t_p99_us"] for r in rows], ys, "k|", markersize=8, label="p99")
    ax2.set_xlabel("time per step (µs; mean, | p99)")
    for y, r in zip(ys, rows):
        ax2.annotate(describe(r) if r["useless"] or r["stable"] != "yes" else "stable, helps", (0, y),
                     xytext=(2, 0), textcoords="offset points", va="center", fontsize=style.SMALL)
    fig.suptitle("%s: green = stable, helps, nothing tunnelled" % name)
    style.save(fig, os.path.join(out, "card"), width=style.TEXT)


def make(a, scene, out):
    os.makedirs(out, exist_ok=True)
    ref = find_reference(a, scene, out)
    runs = sweep(a, scene, out, ref)
    rows = [row(os.path.join(runs, "contacts.0.detector-%s" % m), m) for m in a.methods]
    base = row(os.path.join(runs, "no_force"), "no contact force")
    sentence = judge(rows, base, 1e3 * reader.reference_floor(reader.load_summary(ref))[0])
    write(out, scene_name(scene), ref, rows, base, sentence)
    print("card: %s -> %s: %s" % (scene, os.path.join(out, "card.md"), sentence))


def run(a):
    """study.py card [--scene FILE|NAME] [--out DIR]: that scene's card, or every bundled scene's in
    --results/cards/<scene>/."""
    a.methods = a.methods.split(",") if isinstance(a.methods, str) else a.methods
    if a.scene:
        make(a, a.scene, a.out or os.path.join("cards", scene_name(a.scene)))
        return
    for scene in ["sphere_collision", "cylinder_press", "implant_expansion"]:
        make(a, scene, os.path.join(a.results, "cards", scene))
