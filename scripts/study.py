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
  study.py realtime     realtime.csv, tables/realtime.{md,tex}: collision unit and simulator time per
                        step by method, dt mode (scene, 0.9 dt_crit, implicit 10 dt) and threads
  study.py realtime_grid  realtime_grid.csv, tables/realtime_grid.md: the exact method with implicit
                        Euler at the scene's dt x 2^k (k = 0..6) beside its explicit run: the largest
                        step whose settled error stays within 1.5x, its real-time factor (1, 2 threads)
  study.py swap         swap.csv, tables/swap.md: host and guest swapped (which body carries the grid)
  study.py region       region.csv, tables/region.md: claim (e), region half/full/overlap x margin
  study.py orient       orient.csv, tables/orient.md: claim (a) without its confound
  study.py bullet       bullet.csv, tables/bullet.{md,tex}: Bullet's soft bodies beside the harness
  study.py detection    detection.csv, tables/detection.md: claim (d) as stated, detection alone, every
                        detector timed and scored against CGAL's exact sets on the same states
  study.py ensemble     ensembles.csv: the runs the claims' effects compare (scripts/claims.py's judge), each
                        run again as an ensemble (harness run --ensemble K, --members K, default 5: node
                        orders and a jitter far below the mesh's precision); the judge reads it
  study.py all          every one of them, in this order (or name several: study.py accuracy realtime)
  study.py all --scene FILE --out DIR   (or name some of accuracy ablation convergence refinement realtime swap detection)
                        the same studies on a scene of your own: the same tables, figures and CSV files in DIR
                        (its reference: --reference REF, else made into DIR/references/<name>; its voxels:
                        --voxel V (m) and twice it, else the harness's auto voxel and twice it); nothing in results/
                        (references, region, orient and bullet are about the bundled scenes and claims)
  study.py card         one scene's verdict at a glance: --scene FILE|NAME --out DIR (card.md, card.csv,
                        card.{png,pdf}, the runs and, unless --reference DIR is given, the reference in DIR);
                        without --scene every bundled scene's into results/cards/<scene>/
                        (harness_results/card.py; --methods D1,D2,... the detectors, --set KEY=JSON for every
                        run and the reference, recorded in card.md and card.csv)
  study.py scorecard --method 'NAME=KEY=JSON,...' [--scenes A,B,...] [--out DIR]
                        a method of your own judged over several scenes (default the three bundled ones)
                        beside the built-in detectors by the claims' judge: each scene's card, then per
                        scene whether it is closer to the reference than the best built-in method that
                        does not fail (the error ratio's interval), its time ratio, its failures;
                        DIR/scorecard.{md,csv} (default results/scorecard; harness_results/scorecard.py)
  study.py card|scorecard|accuracy|ablation --method 'NAME=KEY=JSON,KEY=JSON'   (repeatable)
                        a method of your own beside the built-in ones: NAME's rows are the runs with those
                        `harness run --set` overrides (split on the commas outside brackets, braces and
                        quotes: contacts.0.force={"stiffness":500,"damping":0.1} stays whole); its name and
                        overrides are in every table, CSV (columns method, overrides) and plot it reaches
                        (harness_results/methods.py). A run stopped before its forcing ended (--quick,
                        --steps) is warned about and marked (column forced) in the tables.
Options: --harness PATH (default build/bin/harness), --results DIR (default results),
         --quick (short runs, fewer points: a smoke test, not results), -j N (runs at once, default 2),
         --repeats N (runs per configuration for the timings, default 5),
         --plots-only (runs nothing: writes the tables and figures of accuracy, ablation,
         convergence, orient, swap, region, realtime, detection, restriction, regime and bullet again from
         their CSVs in --results, judged under the current rules: helps, useless and the front
         included; the others have none),
         --cached-only (runs nothing: writes a study's files from the runs already cached in
         results/sweeps/; a configuration not run yet is listed with status "not run").
Every study ends by rewriting tables/counts.tex (the counts the report quotes).
Each study is a module of scripts/harness_results/studies/; the rules below are in
scripts/harness_results/rules.py, the runs go through harness_results/runner.py.
"""
import argparse
import sys

from harness_results import needs

needs.numpy_and_matplotlib("study.py")

from harness_results import card, methods, rules, scorecard, studies  # noqa: E402

METHOD_STUDIES = ("card", "scorecard", "accuracy", "ablation")


def method_error(msg):
    """A bad --method: one line, exit status 2 (as argparse's errors)."""
    print("study.py: --method %s" % msg, file=sys.stderr)
    sys.exit(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__ + "\n" + rules.__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", nargs="+", choices=studies.ORDER + ["all", "card", "scorecard"])
    ap.add_argument("--harness", default="build/bin/harness")
    ap.add_argument("--results", default="results")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("-j", dest="jobs", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--members", dest="ensemble", type=int, default=None,
                    help="ensemble: members per run (default 5)")
    ap.add_argument("--cached-only", action="store_true",
                    help="run nothing: write the study's files from the runs already in results/sweeps/, a "
                         "configuration not run yet listed with status 'not run' (stability: failed)")
    ap.add_argument("--classes-only", action="store_true",
                    help="accuracy: make the error runs again (so that every row carries the C++ stability class) "
                         "and keep each row's timings from the committed file where its error reproduces its "
                         "committed twin's (column timings says which); runs no timing repeat")
    ap.add_argument("--plots-only", action="store_true",
                    help="only redraw the figures of the named studies from their CSVs in --results "
                         "(accuracy_time.csv, ablation.csv, convergence.csv); runs nothing")
    ap.add_argument("--scene", help="a scene file or bundled name: card, accuracy and ablation on it, every output "
                                    "in --out (default: the bundled scenes into --results)")
    ap.add_argument("--out", help="with --scene: the output folder (default cards/<name> or studies/<name>)")
    ap.add_argument("--reference", help="with --scene: the reference folder (default: the bundled one for card, "
                                        "else made in --out)")
    ap.add_argument("--voxel", type=float, help="with --scene: the footing voxel in m (the studies take it and twice it; "
                    "default: the harness's auto voxel, the smallest power of two in m at or above the host's mean "
                    "surface edge)")
    ap.add_argument("--scenes", help="scorecard: the scenes, A,B,... (files or bundled names; default %s)" %
                    ",".join(scorecard.SCENES))
    ap.add_argument("--methods", default=",".join(card.METHODS), help="card: the detectors (default %(default)s)")
    ap.add_argument("--set", dest="card_sets", action="append", default=[], help="card: KEY=JSON for every run")
    ap.add_argument("--method", dest="method_specs", action="append", default=[], metavar="NAME=KEY=JSON,...",
                    help="card, accuracy, ablation: a method of your own, the runs with these --set overrides "
                         "(repeatable; commas inside [], {} and quotes belong to the value)")
    a = ap.parse_args()
    try:
        taken = (card.builtin_names(a) if {"card", "scorecard"} & set(a.what) else []) + (
            studies.module("ablation").builtin_names() if "ablation" in a.what else [])
        a.user_methods = methods.parse_all(a.method_specs, taken=taken)
    except methods.MethodError as e:
        method_error(str(e))
    if a.user_methods and not set(a.what) <= set(METHOD_STUDIES):
        method_error("is taken by %s only (not %s)" % (", ".join(METHOD_STUDIES),
                                                      ", ".join(w for w in a.what if w not in METHOD_STUDIES)))
    if a.classes_only and set(a.what) != {"accuracy"}:
        ap.error("--classes-only: the accuracy study only (got %s)" % ", ".join(a.what))
    if a.voxel is not None and (not a.scene or not a.voxel > 0):
        ap.error("--voxel: a size in m above 0, with --scene (got %g%s)" % (a.voxel, "" if a.scene else ", no --scene"))
    if "card" in a.what or "scorecard" in a.what:
        if len(a.what) > 1:
            ap.error("%s is made alone" % a.what[0])
        if "scorecard" in a.what:
            if a.scene:
                ap.error("scorecard: --scenes A,B,... (several scenes), not --scene")
            if a.reference and len((a.scenes or "").split(",")) != 1:
                ap.error("scorecard: --reference with exactly one scene in --scenes")
            scorecard.run(a)
        else:
            card.run(a)
        return
    if a.scene:  # a user's scene: the studies that take one, everything in --out
        if "all" in a.what:
            a.what = [w for w in studies.ORDER if w in studies.USER_STUDIES]
        other = [w for w in a.what if w not in studies.USER_STUDIES]
        if other:
            ap.error("--scene: %s run on the bundled scenes only (with --scene: %s)" % (", ".join(other),
                                                                                      ", ".join(studies.USER_STUDIES)))
        studies.use_user_scene(a)
    studies.run_all(a)


if __name__ == "__main__":
    main()
