"""study.py scorecard: a method of your own judged over several scenes beside the built-in ones, by the
judge the claims use (judge/measure.py, judge/claims.py), and where it stands on each.

For each scene (--scenes A,B,...; default the three bundled paper scenes) the scene's card is made
(card.py: every built-in detector, the run without contact force, each --method; runs cached in
OUT/<scene>/runs/) and each of its runs is measured as the claims measure a run: whether it fails
(it blew up or errored, let a node through, is unstable by its C++ stability class, or stopped
before its loading ended) and its error over the final window against the scene's reference, with
its interval (the window's range widened by the reference's floor). Then, per scene and user method:

  the best built-in   the built-in detector with the least error among those that do not fail;
  error ratio         the method's error over the best built-in's, with its interval (judge/claims.py
                      error_ratio): "closer" where the interval lies below 1, "farther" above,
                      "cannot tell" where it contains 1; a failing run loses to one that does not;
  time ratio          its mean time per step over the best built-in's (one run each, one thread, the
                      card's times: a point, no interval).

Writes OUT/scorecard.md (one line per method across the scenes, then one table per scene) and
OUT/scorecard.csv (one row per scene and run). OUT defaults to --results/scorecard.
"""

import math
import os
import sys

from . import card, reader, writers
from .judge import claims, choices, measure
from .reader import scene_name

SCENES = ["sphere_collision", "cylinder_press", "implant_expansion"]
CLOSER, FARTHER, CANNOT_TELL, FAILS, NO_BUILTIN = "closer", "farther", "cannot tell", "fails", "no built-in passes"


class CardScenes(measure.Scenes):
    """The judge's knowledge of one scene taken from its card's reference (a user's scene has none in
    results/references/): the reference's floor and its surfaces' node spacing at rest."""

    def __init__(self, ref):
        super().__init__(ref)
        self.ref = ref

    def floor_mm(self, scene, kind):
        return 1e3 * reader.reference_floor(reader.load_summary(self.ref))[0]

    def mesh_floor_mm(self):
        return math.nan

    def spacing_mm(self, scene):
        if scene not in self._spacing:
            self._spacing[scene] = measure._spacing(os.path.join(self.ref, "surfaces.csv"))
        return self._spacing[scene]

    def ensemble_of(self, row):
        return None


def judge_row(r, scene):
    """A card row as the judge's measure() reads a study's row: the C++ class (a run that errored:
    failed; one stopped before its loading ended: forced), the window's error figures, the nodes
    through (both bodies'), the card's mean time per step."""
    cls = r.get("verdict") or ""
    if r.get("status") not in (None, "", "ok"):
        cls = "failed"
    elif r.get("forced") == "yes":
        cls = "forced"
    return {"scene": scene, "stability_class": cls, "status": r.get("status"),
            "pos_err_max_mm": r.get("pos_err_max_mm"), "pos_err_max_max_mm": r.get("pos_err_max_max_mm"),
            "pos_err_amp_mm": r.get("pos_err_amp_mm"), "tunnelled": r.get("tunnelled_total"),
            "t_mean_us": r.get("t_mean_us"), "why_unstable": r.get("why_unstable")}


def standing(mine, builtin):
    """(word, error effect or None, time ratio, the best built-in Run or None) of a user's Run against
    the built-in Runs of one scene."""
    passing = [b for b in builtin if not b.failed and b.err == b.err]
    if mine.failed:
        best = min(passing, key=lambda b: b.err) if passing else None
        return FAILS, None, math.nan, best
    if not passing:
        return NO_BUILTIN, None, math.nan, None
    best = min(passing, key=lambda b: b.err)
    eff = claims.error_ratio(mine, best, "", "against %s" % best.label)
    word = {claims.FOR: CLOSER, claims.AGAINST: FARTHER}.get(eff.outcome, CANNOT_TELL)
    t = mine.t / best.t if mine.t == mine.t and best.t == best.t and best.t > 0 else math.nan
    return word, eff, t, best


def measured(a, scene, out, spec):
    """The scene's card made (or its cached runs read) and every run measured: (built-in Runs, user
    Runs, the no-force Run, the reference folder)."""
    rows, base, ref = card.make(a, scene, out)
    scenes = CardScenes(ref)
    name = scene_name(scene)
    user_names = {m.name for m in (getattr(a, "user_methods", None) or [])}
    runs = [measure.measure(judge_row(r, name), spec, scenes, label=r["method"], time_key="t_mean") for r in rows]
    builtin = [x for x in runs if x.label not in user_names]
    user = [x for x in runs if x.label in user_names]
    return builtin, user, measure.measure(judge_row(base, name), spec, scenes, label=card.NO_FORCE,
                                          time_key="t_mean"), ref


COLUMNS = ["scene", "method", "builtin", "fails", "class", "error_mm", "error_lo_mm", "error_hi_mm", "t_mean_us",
           "standing", "against", "error_ratio", "error_ratio_lo", "error_ratio_hi", "time_ratio", "reference"]
HEADS = ["method", "built-in", "fails", "class", "error (mm) [interval]", "µs per step", "standing",
         "error ratio [interval]", "time ratio"]


def g(v, digits=3):
    return claims.g(v, digits)


def run_line(x):
    return {"fails": x.failed or "no", "class": x.cls, "error_mm": x.err, "error_lo_mm": x.err_lo,
            "error_hi_mm": x.err_hi, "t_mean_us": x.t}


def rows_of(scene, builtin, user, base, ref):
    """scorecard.csv's rows of one scene: each built-in run, the no-force run, each user's run with its
    standing."""
    out = [dict(run_line(x), scene=scene, method=x.label, builtin="yes", reference=ref) for x in builtin]
    out.append(dict(run_line(base), scene=scene, method=card.NO_FORCE, builtin="no force", t_mean_us="", reference=ref))
    for x in user:
        word, eff, t, best = standing(x, builtin)
        r = dict(run_line(x), scene=scene, method=x.label, builtin="no", standing=word,
                 against=best.label if best else "", time_ratio=t, reference=ref)
        if eff is not None:
            r.update(error_ratio=eff.value, error_ratio_lo=eff.lo, error_ratio_hi=eff.hi)
        out.append(r)
    return out


def interval(v, lo, hi):
    if v is None or v == "" or v != v:
        return "-"
    return "%s [%s, %s]" % (g(v), g(lo), g(hi))


def summary_line(name, rows):
    """One user method's standing across the scenes, in words."""
    mine = [r for r in rows if r["method"] == name and r["builtin"] == "no"]
    counts = {}
    for r in mine:
        counts.setdefault(r["standing"], []).append(r["scene"])
    parts = ["%s on %d (%s)" % (w, len(s), ", ".join(s)) for w, s in sorted(counts.items())]
    return "**%s**, against the best built-in method that does not fail on each of %d scenes: %s." % (
        name, len(mine), "; ".join(parts) if parts else "no scene")


def write(out, rows, names, spec):
    writers.write_csv(os.path.join(out, "scorecard.csv"), rows, COLUMNS)
    md = ["# Scorecard\n\n",
          "Each method of your own against the built-in method with the least error that does not fail, per "
          "scene: *closer* or *farther* where the interval of the error ratio lies below or above 1, *cannot "
          "tell* where it contains 1, *fails* where the method's run fails (a failing run loses).\n\n"]
    md += ["- " + summary_line(n, rows) + "\n" for n in names]
    md.append("\nA run fails when it blew up or errored, lets a node through, is unstable by its stability class "
              "(the harness's, from the run alone), or stopped before its loading ended. Error: the largest node "
              "distance from the reference's settled surfaces over the final window, its interval the window's "
              "range widened by the reference's floor. Times: mean µs per step of one run, one thread (a point: "
              "compare them as ratios within this card). Judge: `scripts/harness_results/judge/`, choices %s.\n"
              % spec.name())
    for scene in dict.fromkeys(r["scene"] for r in rows):
        sr = [r for r in rows if r["scene"] == scene]
        md.append("\n## %s\n\nReference: `%s`.\n\n" % (scene, sr[0]["reference"]))
        table = [{"method": r["method"], "builtin": r["builtin"], "fails": r["fails"], "class": r["class"],
                  "error": interval(r["error_mm"], r["error_lo_mm"], r["error_hi_mm"]),
                  "t": g(r["t_mean_us"], 4) if r["t_mean_us"] != "" else "-",
                  "standing": r.get("standing", "") + (" (vs %s)" % r["against"] if r.get("against") else ""),
                  "ratio": interval(r.get("error_ratio"), r.get("error_ratio_lo"), r.get("error_ratio_hi")),
                  "time_ratio": g(r.get("time_ratio")) if r.get("time_ratio") not in (None, "") else "-"}
                 for r in sr]
        md.append(writers.md_table(table, ["method", "builtin", "fails", "class", "error", "t", "standing", "ratio",
                                           "time_ratio"], HEADS))
    md.append("\nMade by `scripts/study.py scorecard`; each scene's card and runs are in its folder here.\n")
    writers.write_text(os.path.join(out, "scorecard.md"), "".join(md))


def run(a):
    """study.py scorecard --method NAME=... [--scenes A,B] [--out DIR]."""
    a.methods = a.methods.split(",") if isinstance(a.methods, str) else a.methods
    users = list(getattr(a, "user_methods", None) or [])
    if not users:
        print("study.py scorecard: give the method to judge: --method 'NAME=KEY=JSON,...' (repeatable)", file=sys.stderr)
        sys.exit(2)
    scenes = [s for s in (a.scenes.split(",") if a.scenes else SCENES) if s]
    out = a.out or os.path.join(a.results, "scorecard")
    os.makedirs(out, exist_ok=True)
    spec = choices.DEFAULT
    rows = []
    for scene in scenes:
        builtin, user, base, ref = measured(a, scene, os.path.join(out, scene_name(scene)), spec)
        rows += rows_of(scene_name(scene), builtin, user, base, ref)
    write(out, rows, [m.name for m in users], spec)
    for m in users:
        print("scorecard: " + summary_line(m.name, rows).replace("**", ""))
    print("scorecard: %s" % os.path.join(out, "scorecard.md"))
