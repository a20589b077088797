"""The ensemble study: the runs each claim's error effects rest on (the judge's decisive runs: the
best settings its comparisons name), run again as ensembles (`harness run --ensemble K`: K members
that differ only by node order and an initial jitter far below the mesh's precision, what a user
cannot control) so that the claims' intervals include that spread and a class that flips between
members is seen. The members are spent where they decide something: on the runs a verdict's effect
compares, not on the whole grid.

  -> results/ensembles.csv: per run, its configuration (the study file and row it stands for), the
     members, the class every member shares or `flips` with the counts, the window's position error
     (median over the members of its window mean; the smallest window minimum and the largest window
     maximum over the members), the most nodes through over the members, member 0's figure beside
     the committed row's (the binary that ran the ensemble against the one that made the row), and
     the wall time.

Untimed runs, -j at once; the ensembles already in results/ensembles.csv stand (delete a row to
make it again). The judge (scripts/claims.py) reads the file: a row it names is measured
from its members (judge/measure.py).
"""

import os
import time

from .. import reader, runner, writers
from ..judge import choices, claims
from . import accuracy, regime, restriction
from .common import config_sets, force_label, force_setting, reference_of_kind

MEMBERS = 5
COLUMNS = ["file", "scene", "config", "detector", "eliminator", "response", "force", "voxel_mm", "two_sided", "regime",
           "members", "stability_verdict", "classes", "failed_members", "pos_err_max_mm", "pos_err_max_min_mm",
           "pos_err_max_max_mm", "tunnelled_max", "tunnelled_guest_max", "tunnelled_host_max",
           "committed_pos_err_max_mm", "member0_pos_err_max_mm", "member0_state_hash", "wall_s"]
FIG = "/pairs/0/error_vs_reference/window/pos_err_max/"
TUNNEL = "/pairs/0/error_vs_reference/window/tunnelled/max"
# the nodes through at the end by body, their largest over the members (judge/measure.py nodes_through)
TUNNEL_BY = "/pairs/0/error_vs_reference/tunnelled_%s"
FILES = ("accuracy_time.csv", "regime.csv", "restriction.csv")


def decisive_rows(root):
    """The study rows the judge's error effects compare (as written), each once."""
    data = claims.Data(root)
    out, seen = [], set()
    for res in claims.judge_all(data, choices.DEFAULT):
        for e in res.effects:
            for run in e.runs:
                r = run.row
                if r.get("_file") not in FILES or not reader.present(r.get("pos_err_max_mm")):
                    continue
                key = tuple(sorted((k, str(v)) for k, v in r.items()))
                if key not in seen:
                    seen.add(key)
                    out.append(r)
    return out


def sets_of(a, r):
    """The --set overrides that make the row's run again (its study's own configuration)."""
    voxel = reader.num(r.get("voxel_mm")) / 1e3
    voxel = None if voxel != voxel else voxel
    if r["_file"] == "regime.csv":
        extra = dict(regime.REGIMES)[r["regime"]]
        return regime.sets_of(r["eliminator"], force_setting(r["force"]), voxel, extra)
    if r["_file"] == "restriction.csv":
        for label, det, v, elim, f, extra in restriction.configs(a, r["scene"]):
            resp = restriction.response_name(elim, extra) if label != restriction.NO_FORCE else "none"
            if (label, resp) == (r["config"], r.get("response")):
                return config_sets(det, v, elim, f, extra)
        raise KeyError("no configuration of the restriction study makes %s %s %s" % (
            r["scene"], r["config"], r.get("response")))
    for label, det, v, elim, f, extra in accuracy.method_configs(a, r["scene"]):
        shown = "positions" if elim == "projection" else force_label(f)
        if (label, det, elim, shown) == (r["config"], r["detector"], r["eliminator"], r["force"]) and (
                v is None or voxel is None or abs(v - voxel) < 1e-12):
            return config_sets(det, v, elim, f, extra)
    raise KeyError("no configuration of the accuracy study makes %s %s" % (r["scene"], r["config"]))


def folder_of(r):
    name = "%s_%s_%s_%s_%g_%s" % (r["_file"].split(".")[0], r.get("config", ""), r["eliminator"], r["force"],
                                  reader.num(r.get("voxel_mm")), r.get("regime", "") or r.get("two_sided", ""))
    if r.get("response"):  # restriction.csv: projection with and without its bound share the rest
        name += "_" + r["response"]
    return "ensemble/%s/%s" % (r["scene"], "".join(c if c.isalnum() or c in "._-" else "_" for c in name))


def row_of(r, s, members, wall):
    ens = (s or {}).get("ensemble") or {}
    figs = ens.get("figures") or {}
    classes = ens.get("classes") or {}
    fig = lambda k, what: reader.num((figs.get(FIG + k) or {}).get(what)) * 1e3  # noqa: E731
    member_runs = ens.get("member_runs") or []
    return {"file": r["_file"], "scene": r["scene"], "config": r.get("config", ""), "detector": r.get("detector", ""),
            "eliminator": r["eliminator"], "response": r.get("response", ""), "force": r["force"], "voxel_mm": r.get("voxel_mm", ""),
            "two_sided": r.get("two_sided", ""), "regime": r.get("regime", ""), "members": members,
            "stability_verdict": ens.get("stability_verdict", (s or {}).get("status", "failed")),
            "classes": ";".join("%s:%d" % kv for kv in sorted(classes.items())),
            "failed_members": sum(1 for m in member_runs if m.get("status") not in (None, "ok")) if member_runs else members,
            "pos_err_max_mm": fig("mean", "median"), "pos_err_max_min_mm": fig("min", "min"),
            "pos_err_max_max_mm": fig("max", "max"),
            "tunnelled_max": reader.num((figs.get(TUNNEL) or {}).get("max")),
            "tunnelled_guest_max": reader.num((figs.get(TUNNEL_BY % "guest") or {}).get("max")),
            "tunnelled_host_max": reader.num((figs.get(TUNNEL_BY % "host") or {}).get("max")),
            "committed_pos_err_max_mm": r.get("pos_err_max_mm"),
            "member0_pos_err_max_mm": reader.num(reader.window_figures(s).get("pos_err_max_mm")) if s else float("nan"),
            "member0_state_hash": (s or {}).get("state_hash", ""), "wall_s": "%.1f" % wall}


def run(a, rounds=3):
    """Rounds of: the decisive rows under the judge as it reads results/ensembles.csv so far, each
    missing one run as an ensemble, the file written again; until a round adds none (a run that an
    ensemble shows failing hands the comparison to the next best setting, which is then run too),
    at most `rounds` rounds. Runs already made are cached (results/sweeps/ensemble/)."""
    members = getattr(a, "ensemble", None) or MEMBERS
    t0 = time.monotonic()
    path = os.path.join(a.results, "ensembles.csv")
    # The ensembles already in the file stand and stay (a run an ensemble showed failing is no longer
    # decisive, but the judge still reads its ensemble); the study runs the missing ones.
    done = committed(path)
    for k in range(rounds):
        rows = decisive_rows(a.results)
        todo = [r for r in rows if folder_of(r) not in done]
        print("study: ensemble, round %d: %d runs the claims' effects compare, %d not yet run as ensembles of %d" % (
            k + 1, len(rows), len(todo), members))
        if not todo:
            break

        def one(r):
            # the row's own reference: restriction.csv's rows against the scene's (two-sided) one
            compare = True
            if r["_file"] != "restriction.csv":
                kind, ref, other = reference_of_kind(a, r["scene"], r.get("two_sided") == "yes")
                compare = (ref, other)
            start = time.monotonic()
            s = runner.run(a, r["scene"], os.path.join(a.results, "sweeps", folder_of(r)),
                           sets_of(a, r) + ["--ensemble=%d" % members], compare=compare)
            return row_of(r, s, members, time.monotonic() - start)
        for r, out in zip(todo, runner.parallel(a, one, todo)):
            done[folder_of(r)] = out
        writers.write_csv(path, list(done.values()), COLUMNS)
    print("study: ensemble: %d runs in %.0f s -> %s" % (len(done), time.monotonic() - t0, path))


def committed(path):
    """{folder: row} of the ensembles already in `path` (none without the file): a run made once is
    not made again (delete its row to make it again)."""
    rows = reader.read_csv(path, text=tuple(COLUMNS), missing=[])
    return {folder_of(dict(r, _file=r["file"])): {c: r.get(c, "") for c in COLUMNS} for r in rows}
