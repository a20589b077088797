"""study.py bullet: the peer engine. Bullet's soft bodies (`--engine bullet`, four margin and iteration
settings) on the variants of the scenes that Bullet can represent (experiments/scenes/bullet/: linear
springs, no dashpot), against the converged reference of the same variant, beside three of the
harness's methods on the same variant -> bullet.csv, tables/bullet.{md,tex}, tables/bullet_note.tex, references/bullet_<scene>.
"""

import os

from .. import reader, runner, writers
from .common import STUDY_EVERY, config_sets, figures, read_rows, table_path
from .common import columns_of

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
        runner.reference(a, "bullet/" + scene, work, quick_levels=2, cached=False)
        runner.install_reference(work, dest)
    return dest


def bullet_run(a, scene, out, args, sets, ref):
    """One run of a Bullet variant (`args`: the engine's options), compared with the variant's reference."""
    return runner.harness(a, ["run", "bullet/" + scene, "--out", out, "--quiet", "--compare", ref, "--set",
                              "output.frames_every=0"] + (["--set", "time.settle.max_steps=400"] if a.quick else []) +
                          ["--set", "references.every=%d" % STUDY_EVERY] + args + runner.sets_args(sets + a.extra_sets),
                          out)


def run(a):
    jobs = []
    for scene in BULLET_SCENES:
        ref = bullet_reference(a, scene)
        for label, args, sets in BULLET_CONFIGS:
            folder = label.replace(" ", "_").replace(",", "").replace("(", "").replace(")", "")
            out = os.path.join(a.results, "sweeps", "bullet", scene, folder)
            jobs.append((scene, label, out, args, sets, ref))
    sums = runner.parallel(a, lambda j: bullet_run(a, j[0], j[2], j[3], j[4], j[5]), jobs)
    rows = []
    for (scene, label, out, args, sets, ref), s in zip(jobs, sums):
        e = reader.engine(s)
        conv = reader.reference_converged(reader.load_summary(ref))
        f = figures(s)
        if e.get("name") == "bullet":  # no work booked: stable = finite (figures() reads the audit as closed)
            f["stable"] = "yes" if reader.status(s) == "ok" else "no"
        rows.append(dict(f, scene=scene, config=label, engine=e.get("name", "harness"),
                         engine_version=reader.version(s, "Bullet") or "" if e.get("name") == "bullet" else "",
                         margin_mm=1e3 * max(e.get("margin_m") or [float("nan")]), **reader.end_figures(s),
                         max_depth_peak_mm=reader.pair_figures(s)["max_depth_peak_mm"],
                         reference_converged="yes" if conv is True else "no",
                         machine=reader.step_distribution(s)["machine"], jobs=a.jobs))
    writers.write_csv(os.path.join(a.results, "bullet.csv"), rows, columns_of(COLUMNS, rows))
    tables(a, read_rows(a, "bullet.csv"))


COLUMNS = ["scene", "config", "engine", "engine_version", "margin_mm", "stable", "settled", "steps", "residual",
           "kinetic_energy_final", "pos_err_max_mm", "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final",
           "t_contact_us", "t_step_us", "reference_converged", "machine", "jobs"]


def timing_note(rows):
    """How the rows' times were taken: runs `jobs` at a time on the machine they recorded (untimed:
    indicative only); the note of a file written before those columns says it does not know."""
    jobs = sorted({"%d" % reader.num(r["jobs"]) for r in rows if reader.present(r.get("jobs"))})
    machines = sorted({r.get("machine") for r in rows if r.get("machine")})
    if not jobs:
        return "untimed runs, how many at a time not recorded (bullet.csv before its `jobs` column): the times are indicative only"
    return "untimed runs %s at a time on %s: the times are indicative only" % (
        " or ".join(jobs), "; ".join(machines) or "a machine not recorded")


def tables(a, rows):
    """tables/bullet.{md,tex} and bullet_note.tex (\\BulletTiming: how the times were taken, for the
    report's caption) from bullet.csv's rows (as read back: --plots-only gives the same)."""
    version = next((r["engine_version"] for r in rows if r.get("engine_version")), "(version not recorded)")
    note = timing_note(rows)
    md = ["# The peer engine: Bullet's soft bodies\n\n",
          "`harness run bullet/SCENE --engine bullet` (Bullet %s, reference/bullet_engine.hpp: the same nodes, "
          "masses, pins and drivers, links of the same rest lengths with kLST = k dt^2 (1/m_a + 1/m_b) / iterations, "
          "velocity damping kDP = mass_damping x dt, vertex-face soft-soft contact VF_SS with the margin shown) beside "
          "three of the harness's methods, on the variants Bullet can represent (experiments/scenes/bullet/: linear "
          "springs, no dashpot), against the reference solution of the same variant. Errors over the final "
          "window (mm, as in accuracy_time.md); residual: the force residual at the end (settled: below the "
          "scene's tolerance, %s, for 100 steps); t_contact: detection (and for the harness elimination) per step, µs, median; t_step: the "
          "whole step; %s. Bullet's contact response is solved inside its position solver with the links: its "
          "t_contact is its collision pass alone. Made by `scripts/study.py bullet`.\n\n" % (version, "1e-5", note),
          writers.md_table(rows, ["scene", "config", "margin_mm", "stable", "settled", "residual", "pos_err_max_mm",
                                  "gap_max_mm", "depth_max_mm", "max_depth_peak_mm", "true_pen_final", "t_contact_us",
                                  "t_step_us", "reference_converged"],
                           ["scene", "method", "margin (mm)", "stable", "settled", "residual", "pos. error (mm)",
                            "gap (mm)", "depth (mm)", "peak depth (mm)", "pen. final", "contact (µs, untimed)",
                            "step (µs, untimed)", "reference converged"])]
    with open(table_path(a, "bullet.md"), "w") as f:
        f.write("".join(md))
    with open(table_path(a, "bullet.tex"), "w") as f:
        f.write(writers.tex_table(rows, ["scene", "config", "margin_mm", "settled", "residual", "pos_err_max_mm",
                                         "gap_max_mm", "depth_max_mm", "true_pen_final", "t_contact_us", "t_step_us"],
                                  ["scenario", "method", "margin (mm)", "settled", "residual", "pos.\\ err. (mm)",
                                   "gap (mm)", "depth (mm)", "pen.", "contact ($\\mu$s, untimed)",
                                   "step ($\\mu$s, untimed)"],
                                  "Bullet against the harness on the Bullet variants (%s)" % note))
    with open(table_path(a, "bullet_note.tex"), "w") as f:  # the report's caption says how the times were taken
        f.write("%% made by scripts/study.py bullet from bullet.csv\n\\newcommand{\\BulletTiming}{%s}\n" %
                writers.tex_escape(note))


def plots(a):
    """tables/bullet.{md,tex} again from bullet.csv (nothing is run)."""
    if os.path.exists(os.path.join(a.results, "bullet.csv")):
        tables(a, read_rows(a, "bullet.csv"))
