"""study.py realtime: steps per second of the bundled scenes on one core (one thread, no references,
no frames), --repeats runs one after the other (never cached: timings) -> realtime.csv,
tables/realtime.{md,tex}.
"""

import os

from .. import reader, rules, runner, writers
from .common import SCENES, table_path


def run(a):
    """Steps per second of the bundled scenes on one core (one thread, no references, no frames),
    --repeats runs one after the other; the run with the median mean step, and the range."""
    rows = []
    for scene in SCENES:
        runs = []
        for r in range(a.repeats):
            out = os.path.join(a.results, "sweeps", "realtime", "%s_%d" % (scene, r))
            s = runner.harness(a, ["run", scene, "--out", out, "--quiet", "--set", "references.solvers=[]",
                                   "--set", "output.frames_every=0"] + runner.sets_args(a.extra_sets), out,
                               check=True, cached=False)
            per_step = sorted(v for v in reader.load_steps(out)["t_step_us"] if reader.present(v))
            mean = sum(per_step) / len(per_step)
            runs.append({"scene": scene, "nodes": reader.nodes(s), "steps": reader.steps_run(s), "mean_us": mean,
                         "median_us": rules.median(per_step),
                         "p99_us": per_step[min(len(per_step) - 1, int(0.99 * len(per_step)))],
                         "contact_us": reader.contact_time_us(s),
                         "steps_per_s": 1e6 / mean, "realtime_factor": reader.scene_dt(s) * 1e6 / mean})
        runs.sort(key=lambda r: r["mean_us"])
        row = dict(runs[len(runs) // 2])
        row["steps_per_s_range"] = "%.0f-%.0f" % (runs[-1]["steps_per_s"], runs[0]["steps_per_s"])
        row["runs"] = len(runs)
        rows.append(row)
    cols = ["scene", "nodes", "steps", "mean_us", "median_us", "p99_us", "contact_us", "steps_per_s",
            "realtime_factor", "steps_per_s_range", "runs"]
    heads = ["scene", "nodes", "steps", "mean step (µs)", "median step (µs)", "p99 step (µs)", "detect+elim (µs)",
             "steps/s", "real-time factor", "steps/s over the runs", "runs"]
    writers.write_csv(os.path.join(a.results, "realtime.csv"), rows, cols)
    with open(table_path(a, "realtime.md"), "w") as f:
        f.write("# Real time on one core\n\nThe bundled scenes with their default contact, one thread, no "
                "references, no frames; steps/s = 1 / mean step (every step counted); real-time factor = simulated "
                "seconds per wall second. The run (of %d) with the median mean; the range over the runs. Made by "
                "`scripts/study.py realtime`; timings vary from run to run.\n\n" % a.repeats
                + writers.md_table(rows, cols, heads))
    with open(table_path(a, "realtime.tex"), "w") as f:
        tcols = ["scene", "steps", "mean_us", "median_us", "steps_per_s", "realtime_factor", "steps_per_s_range"]
        shown = [{c: (("%.3g" % r[c]) if isinstance(r[c], float) else r[c]) for c in tcols} for r in rows]
        f.write(writers.tex_table(shown, tcols, ["scene", "steps", "mean ($\\mu$s)", "median ($\\mu$s)", "steps/s",
                                                 "real-time factor", "steps/s, %d runs" % a.repeats],
                                  "Steps per second on one core"))
