"""study.py card: one scene's verdict at a glance (docs/tutorial.md). The scene's contact run with
each detector (its own eliminator and force), beside the same scene with no contact force, every
run compared with the scene's converged reference and judged as the studies judge (rules.py):
error over the final window, its swing, stability class, tunnelling, "helps" (rules.useful against
the no-force run), time per step (mean and 99th percentile of steps.csv's t_step_us: one run at a
time, one thread). Writes OUT/card.md, OUT/card.csv, OUT/card.{png,pdf}; the runs are a
`harness sweep --baseline` in OUT/runs/ (cached: delete it to rerun), the reference (when none is
given) a `harness reference` in OUT/reference/.

A user's method (study.py card --method NAME=KEY=JSON,...: methods.py) is a row beside the
detectors': one `harness run` with its overrides in OUT/runs/method-NAME-HASH/. Every row records
the overrides it ran with (card.csv and card.md `overrides`: --set's, and the detector's or the
method's), card.md says the --set ones in words and the figure notes them; a run stopped before its
forcing ended is warned about on stderr and marked (`forced` yes).
"""

import json
import math
import os
import subprocess
import sys

from . import methods, reader, rules, runner, style, writers
from .reader import scene_name

METHODS = ["voxel", "voxel_exact", "cgal"]
EVERY = 10  # CGAL measures every run every EVERY steps, as in every study (studies/common.py STUDY_EVERY)


NO_FORCE = "no contact force"


def builtin_names(a):
    """The names of the card's built-in rows (its detectors, the run without contact force), which a
    user's method (--method) may not take."""
    return (a.methods.split(",") if isinstance(a.methods, str) else list(a.methods)) + [NO_FORCE, "no_force"]


def protocol_sets():
    """The --set overrides of every run of the card, before the user's: no frames, CGAL every EVERY steps."""
    return ["output.frames_every=0", 'references.solvers=["cgal"]', "references.every=%d" % EVERY]


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
        sets = protocol_sets() + a.card_sets
        cmd = [a.harness, "sweep", scene, "--grid", "contacts.0.detector=" + ",".join(a.methods), "--baseline",
               "--compare", ref, "--out", runs, "-j", "1"] + sum((["--set", s] for s in sets), [])
        subprocess.run(cmd, check=True, env=dict(os.environ, HARNESS_THREADS="1"))
    return runs


def method_run(a, scene, runs, ref, m):
    """A user's method (--method): one `harness run` of the scene with the card's overrides, --set's and
    then the method's, compared with the reference, on one thread, into RUNS/method-NAME-HASH (a hash
    of --set's and its overrides: cached until they change). Its folder; a run the harness refuses
    ends the card (exit 2, after the harness's line)."""
    folder = os.path.join(runs, methods.folder(m, a.card_sets))
    if not all(reader.stored(os.path.join(folder, n)) for n in ("steps.csv", "timing.csv")):
        cmd = [a.harness, "run", scene, "--out", folder, "--quiet", "--compare", ref] + runner.sets_args(
            protocol_sets() + a.card_sets + m.sets)
        print("card: %s: %s" % (m.name, " ".join(cmd)))
        p = subprocess.run(cmd, env=dict(os.environ, HARNESS_THREADS="1"))
        if p.returncode != 0 and not reader.has_summary(folder):  # refused (its line is above): say whose
            print("card: --method %s: the harness refused its run (exit %d)" % (m.name, p.returncode), file=sys.stderr)
            sys.exit(2 if p.returncode == 2 else 1)
    return folder


def step_times(folder):
    """(mean, p99, max) of the run's per-step times, us (the first pair's rows of steps.csv)."""
    cols = reader.load_steps(folder)
    first = cols["pair"][0] if cols.get("pair") else None
    t = sorted(v for v, p in zip(cols["t_step_us"], cols.get("pair", [first] * len(cols["t_step_us"])))
               if p == first and reader.present(v))
    if not t:
        return math.nan, math.nan, math.nan
    return sum(t) / len(t), t[min(len(t) - 1, int(math.ceil(0.99 * len(t))) - 1)], t[-1]


def row(folder, method, overrides=()):
    """A run's row of the card: its figures, `method` (its name), `overrides` (the --set values it ran
    with beyond the card's protocol_sets, as KEY=JSON,KEY=JSON) and `forced` (yes: it stopped before its
    forcing ended, runner.warn_forced says so on stderr)."""
    s = reader.load_summary(folder)
    f = dict(reader.window_figures(s), **rules.stability_fields(s))
    mean, p99, mx = step_times(folder)
    runner.warn_forced(folder, s)
    return dict(f, method=method, folder=os.path.basename(folder), t_mean_us=mean, t_p99_us=p99, t_max_us=mx,
                tunnelled_total=reader.tunnelled_both(s), overrides=methods.text(overrides),
                forced="yes" if runner.forcing_cut(s) else "no")


def judge(rows, base, floor_mm=0.0):
    """Each row's helps / useless words, and the one-sentence verdict: the closest of the stable
    methods that help, or those within the noise of it (rules.noise: 10 %, the two swings, the
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
           "useless", "t_mean_us", "t_p99_us", "t_max_us", "why_unstable", "forced", "folder", "overrides"]
HEADS = ["method", "error (mm)", "error swing (mm)", "depth (mm)", "stability", "tunnelled", "helps", "useless",
         "step mean (µs)", "step p99 (µs)", "step max (µs)", "why unstable", "still forced", "run", "overrides"]


def overrides_text(card_sets, user):
    """card.md's lines on what the runs were given beyond the scene: --set (every run and the
    reference) and each user's method's overrides; `user`: [(name, its own overrides)]."""
    out = ["Overrides (`--set`, every run and the reference): %s." % (
        ", ".join("`%s`" % x for x in card_sets) if card_sets else "none: the scene as written")]
    for name, sets in user:
        out.append("Method `%s` (`--method`): the scene with `%s` (after the `--set` ones)." % (name, methods.text(sets)))
    return "".join(line + "\n\n" for line in out)


def forced_text(rows):
    """card.md's line on the runs stopped before their forcing ended; "" when none was."""
    forced = [r["method"] for r in rows if r.get("forced") == "yes"]
    if not forced:
        return ""
    return ("**Still forced when they stopped** (`--steps`, `time.steps` or a settle limit cut them before their "
            "drivers finished; column `still forced`): %s: their figures are of a body still being loaded, not of "
            "where it settles.\n\n" % ", ".join(forced))


def write(out, name, ref, rows, base, sentence, card_sets=(), user=()):
    """OUT/card.csv, card.md and card.{png,pdf} from the rows (built-in and the user's methods') and
    the run without contact force; `card_sets`: --set, `user`: [(name, its own overrides)] of the
    user's methods, both recorded."""
    floor_m, floor_rule = reader.reference_floor(reader.load_summary(ref))
    conv = reader.reference_converged(reader.load_summary(ref))
    if not conv:
        sentence = ("Judged against a reference that did not converge (floor %.3g mm: differences below it are not "
                    "told apart): " % (1e3 * floor_m)) + sentence
    # The no-force run still detects (its force is 0): its time is not a method's, and is not shown.
    all_rows = rows + [dict(base, method=NO_FORCE, helps="", useless="", t_mean_us="", t_p99_us="", t_max_us="")]
    writers.write_csv(os.path.join(out, "card.csv"), all_rows, COLUMNS)
    md = ["# %s: the verdict card\n\n" % name, sentence + "\n\n", overrides_text(list(card_sets), list(user)),
          forced_text(all_rows),
          writers.md_table([dict(r, overrides=r["overrides"].replace("|", "\\|")) for r in all_rows], COLUMNS, HEADS),
          "\nError: the largest node distance from the reference's settled surfaces, mean over the final window "
          "(swing: its max - min there); depth: the deepest true penetration (CGAL) in the window. Reference: `%s`, "
          "%s, floor %.3g mm (%s): errors closer than that are not told apart. Stability and \"helps\" by the studies' "
          "rules (`scripts/study.py --help`); times from one run at a time on one thread, measurement excluded (the "
          "run with no contact force still detects: no time is given for it). "
          "Runs: `%s`. Made by `scripts/study.py card`.\n" % (
              ref, "converged" if conv else "NOT converged", 1e3 * floor_m, floor_rule, os.path.join(out, "runs"))]
    writers.write_text(os.path.join(out, "card.md"), "".join(md))
    plot(out, name, rows, base, 1e3 * floor_m, card_sets, user)


def plot_note(card_sets, user):
    """The figure's note of the overrides (--set, --method), wrapped; "" without any."""
    import textwrap
    lines = (["--set (every run): " + methods.text(card_sets)] if card_sets else []) + [
        "%s (--method): %s" % (n, methods.text(sets)) for n, sets in user]
    return "\n".join(textwrap.fill(x, 110, break_on_hyphens=False) for x in lines)


def plot(out, name, rows, base, floor_mm, card_sets=(), user=()):
    plt = style.pyplot()
    note = plot_note(list(card_sets), list(user))
    height = max(1.3, 0.5 + 0.3 * len(rows)) + (0.25 + 0.13 * note.count("\n") if note else 0.0)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(style.TEXT, height), layout="constrained", sharey=True)
    ys = list(range(len(rows)))
    colour = ["C2" if r["stable"] == "yes" and not r["useless"] else "0.6" for r in rows]
    ax1.barh(ys, [min(r["pos_err_max_mm"], 1e3) for r in rows], color=colour,
             xerr=[[0] * len(rows), [r["pos_err_amp_mm"] if r["pos_err_amp_mm"] == r["pos_err_amp_mm"] else 0 for r in rows]])
    ax1.axvline(base["pos_err_max_mm"], color="C3", ls="--", label="no contact force")
    if floor_mm == floor_mm:
        ax1.axvspan(0, floor_mm, color="0.85", label="reference floor")
    ax1.set_yticks(ys, [r["method"] for r in rows])
    ax1.set_xlabel("error over the window (mm; whisker: swing)")
    ax1.legend(loc="best", fontsize=style.SMALL)
    ax2.barh(ys, [r["t_mean_us"] for r in rows], color=colour)
    ax2.plot([r["t_p99_us"] for r in rows], ys, "k|", markersize=8, label="p99")
    ax2.set_xlabel("time per step (µs; mean, | p99)")
    for y, r in zip(ys, rows):
        ax2.annotate((describe(r) if r["useless"] or r["stable"] != "yes" else "stable, helps") +
                     ("; still forced when it stopped" if r.get("forced") == "yes" else ""), (0, y),
                     xytext=(2, 0), textcoords="offset points", va="center", fontsize=style.SMALL)
    fig.suptitle("%s: green = stable, helps, nothing tunnelled" % name)
    if note:
        fig.supxlabel(note, fontsize=style.SMALL, ha="left", x=0.01)
    style.save(fig, os.path.join(out, "card"), width=style.TEXT)


def make(a, scene, out):
    os.makedirs(out, exist_ok=True)
    ref = find_reference(a, scene, out)
    runs = sweep(a, scene, out, ref)
    user = list(getattr(a, "user_methods", None) or [])
    rows = [row(os.path.join(runs, "contacts.0.detector-%s" % m), m,
                ["contacts.0.detector=%s" % json.dumps(m)] + a.card_sets) for m in a.methods]
    rows += [row(method_run(a, scene, runs, ref, m), m.name, a.card_sets + m.sets) for m in user]
    base = row(os.path.join(runs, "no_force"), NO_FORCE, a.card_sets)
    sentence = judge(rows, base, 1e3 * reader.reference_floor(reader.load_summary(ref))[0])
    write(out, scene_name(scene), ref, rows, base, sentence, a.card_sets, [(m.name, m.sets) for m in user])
    print("card: %s -> %s: %s" % (scene, os.path.join(out, "card.md"), sentence))
    return rows, base, ref


def run(a):
    """study.py card [--scene FILE|NAME] [--out DIR]: that scene's card, or every bundled scene's in
    --results/cards/<scene>/."""
    a.methods = a.methods.split(",") if isinstance(a.methods, str) else a.methods
    if a.scene:
        make(a, a.scene, a.out or os.path.join("cards", scene_name(a.scene)))
        return
    for scene in ["sphere_collision", "cylinder_press", "implant_expansion"]:
        make(a, scene, os.path.join(a.results, "cards", scene))
