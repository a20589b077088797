"""study.py restriction: claim (c) with a practical bound, every response timed under one protocol.

Per scene and detector (the paper's grid at the pair's voxel size, and CGAL): the penalty force (k =
500 N/m along the line), the restriction with its practical bound (the `volume` eliminator: the
layered depth images' shared volume and gradient, one mass-weighted Newton step; docs/findings.md),
projection without a bound, and projection with the exact bound (CGAL's corefinement of the two
surfaces on the same states, references.volume, timed apart as t_bound_us); and the scene with no
contact force, the run a useful setting must beat. Each configuration: one error run (settled,
against the reference over the final window) and --repeats timing runs that each do the same work
(the scene's steps, no settling, no references), one at a time in rounds (runner.repeated, run_all).
-> restriction.csv, tables/restriction.md. On a user's scene (--scene) the same, with its footing
voxel.
"""

import os

from .. import reader, rules, runner, writers
from .accuracy import BOUND, FOOTING_VOXELS, NO_FORCE, bound_time_us
from .common import (PENALTY, STUDY_EVERY, combine, config_sets, timing_runs, folder_name, footing_voxels, force_label, read_rows,
                     scenes, table_path)
from .common import columns_of

# The responses compared, (eliminator, force, extra sets): the force rule is not used by projection
# and volume (their force column reads "positions" and "volume").
RESPONSES = [("line", PENALTY, []), ("volume", "auto", []), ("projection", "auto", []), ("projection", "auto", [BOUND])]


def detectors(a, scene):
    """(label, detector, voxel or None): the paper's grid at the pair's voxel size (the smaller footing
    voxel) and CGAL."""
    v = footing_voxels(a, scene, FOOTING_VOXELS)[0]
    return [("voxel %g mm" % (1e3 * v), "voxel", v), ("cgal", "cgal", None)]


def configs(a, scene):
    """(label, detector, voxel, eliminator, force, extra) of the study on `scene`."""
    out = [(label, det, v, e, f, x) for label, det, v in detectors(a, scene) for e, f, x in RESPONSES]
    v0 = detectors(a, scene)[0][2]
    out.append((NO_FORCE, "voxel", v0, "line", "0", []))
    return out


def response_name(elim, extra):
    """The response as the tables name it."""
    if elim == "projection":
        return "projection + exact bound" if BOUND in extra else "projection"
    return {"line": "penalty", "volume": "volume (LDI bound)"}.get(elim, elim)


def spread(summaries, key):
    """(min, max) over the timing repeats of a per-run statistic (reader.step_distribution's key)."""
    v = sorted(reader.step_distribution(s)[key] for s in timing_runs(summaries))
    return v[0], v[-1]


def run(a):
    rows, jobs, index = [], [], []
    for scene in scenes(a):
        for label, det, v, elim, force, extra in configs(a, scene):
            folder = folder_name(scene, label, elim + ("_bound" if BOUND in extra else ""), force)
            js = runner.repeated(a, scene, "restriction/" + folder, config_sets(det, v, elim, force, extra))
            if BOUND in extra:  # its timing runs also time the bound (outside the step), one at a time
                js = js[:1] + [(sc, out, [x for x in sets if x != "references.solvers=[]"] +
                                ['references.solvers=["cgal"]', BOUND, "references.every=%d" % STUDY_EVERY], cmp, rnd)
                               for sc, out, sets, cmp, rnd in js[1:]]
            index.append((scene, label, det, v, elim, force, extra, len(jobs), len(js)))
            jobs += js
    sums = runner.run_all(a, jobs)
    for scene, label, det, v, elim, force, extra, i, n in index:
        s = sums[i:i + n]
        r = dict(combine(s), scene=scene, config=label, detector=det, eliminator=elim,
                 response=response_name(elim, extra) if label != NO_FORCE else "none",
                 force=force_label(force) if elim == "line" else ("positions" if elim == "projection" else elim),
                 voxel_mm=1e3 * v if v else float("nan"),
                 # the volume's Newton step moves both bodies; the penalty and projection the guest alone
                 two_sided="yes" if elim == "volume" else "no",
                 t_bound_us=rules.median([bound_time_us(j[1]) for j in jobs[i + 1:i + n]] or
                                         [bound_time_us(jobs[i][1])]) if BOUND in extra else float("nan"))
        for key in ("contact_mean", "contact_p99", "eliminate_mean", "eliminate_p99", "eliminate_median"):
            r["t_%s_min_us" % key], r["t_%s_max_us" % key] = spread(s, key + "_us")
        r["status"] = reader.status(s[0])
        rows.append(r)
    write(a, rows)


COLUMNS = ["scene", "config", "detector", "eliminator", "response", "force", "voxel_mm", "two_sided", "stable", "stability",
           "why_unstable", "helps", "useless", "pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm", "depth_max_mm",
           "tunnelled", "contact_power_ratio", "rho_norm", "t_contact_us", "t_contact_min_us", "t_contact_max_us",
           "t_contact_mean_us", "t_contact_mean_min_us", "t_contact_mean_max_us", "t_contact_p99_us",
           "t_contact_p99_min_us", "t_contact_p99_max_us", "t_eliminate_mean_us", "t_eliminate_mean_min_us",
           "t_eliminate_mean_max_us", "t_eliminate_p99_us", "t_eliminate_p99_min_us", "t_eliminate_p99_max_us",
           "t_eliminate_median_us", "t_eliminate_median_min_us", "t_eliminate_median_max_us", "t_step_us",
           "t_step_mean_us", "t_step_p99_us", "t_bound_us", "repeats", "steps", "status", "machine"]


def write(a, rows):
    """restriction.csv and tables/restriction.md from the study's rows (helps and useless against the
    study's own run with no contact force)."""
    bases = {r["scene"]: r for r in rows if r["config"] == NO_FORCE}
    rules.mark_useless(rows, bases)
    writers.write_csv(os.path.join(a.results, "restriction.csv"), rows, columns_of(COLUMNS, rows))
    rows = read_rows(a, "restriction.csv")  # the table from the file as written: --plots-only gives the same
    for r in rows:
        r["steps"] = "%d" % r["steps"] if reader.present(r.get("steps")) else ""
    repeats = int(max((reader.num(r.get("repeats"), a.repeats) for r in rows), default=a.repeats))
    md = ["# Claim (c): what a restriction's bound costs\n\n",
          "Per scene and detector: the penalty force (k = 500 N/m along the line), the restriction with a "
          "practical bound (`volume`: the shared volume and its gradient by layered depth images, one "
          "mass-weighted Newton step per step), projection without a bound, and projection with the exact "
          "bound (CGAL's corefinement of the two surfaces on the same states, its time apart: bound). Errors "
          "over the final window against the reference, mm; time: detection plus response, µs per step, of "
          "%d timing runs that each do the same work (the scene's steps, no settling, no references), one at "
          "a time: the pooled mean, the median 99th percentile and the median of the medians (the response alone: "
          "its part without the detection; the volume restriction uses no contact the detector finds); the bound: "
          "median over the timing runs' measured steps (every %d, outside the step's time), median over the runs. "
          "A run that failed (not finite) stopped early: its times are over the steps it ran. Machine: %s. Made by `scripts/study.py restriction`.\n\n"
          % (repeats, STUDY_EVERY, next((r["machine"] for r in rows if r.get("machine")), "not recorded"))]
    for scene in scenes(a):
        sr = [r for r in rows if r["scene"] == scene]
        md.append("## %s\n\n" % scene)
        md.append(writers.md_table(sr, ["config", "response", "stability", "useless", "pos_err_max_mm",
                                        "pos_err_amp_mm", "depth_max_mm", "tunnelled", "steps", "t_contact_mean_us",
                                        "t_contact_p99_us", "t_contact_us", "t_eliminate_mean_us", "t_bound_us",
                                        "why_unstable"],
                                   ["detector", "response", "stability", "useless", "pos. error max (mm)",
                                    "error swing (mm)", "depth max (mm)", "tunnelled", "steps run", "mean (µs)",
                                    "p99 (µs)", "median (µs)", "response alone, mean (µs)", "bound (µs)",
                                    "why unstable"]))
        md.append("\n")
    with open(table_path(a, "restriction.md"), "w") as f:
        f.write("".join(md))


def plots(a):
    """tables/restriction.md again from restriction.csv (nothing is run)."""
    write(a, read_rows(a, "restriction.csv"))
