"""Real time (the paper's aim): simulated seconds per wall second of each stable method of
results/accuracy_time.csv, dt over its median step (physics, detection and elimination). Verdict:
supported when every stable method runs at least in real time, partly when some does, not supported
when none does.
"""

import math

from .. import reader
from .c_restrictions import accuracy_rows
from .common import SCENE_ORDER, Verdict


def scene_dt(scene):
    """The bundled scene's time step (s), or None."""
    try:
        return float(reader.bundled_scene(scene)["time"]["dt"])
    except (OSError, KeyError, ValueError):
        return None


def judge(ctx):
    rows = accuracy_rows(ctx)
    if not rows:
        return Verdict("realtime", "not tested")  # said once, in (c)'s section
    md = ["## Real time", "",
          "Real-time factor = dt / median step time (physics, detection and elimination; the accuracy runs, two "
          "at once on this two-core machine, no frames); at least 1 is real time. Per scenario, the stable methods "
          "from the fastest step to the slowest.", "",
          "| scenario | dt (s) | method | elim. | force | step (µs) | steps/s | real-time factor |",
          "|---|---:|---|---|---|---:|---:|---:|"]
    rtf = []
    for scene in SCENE_ORDER:
        dt = scene_dt(scene)
        st = sorted((r for r in rows if r["scene"] == scene and r["stable"] == "yes" and r["t_step_us"] > 0),
                    key=lambda r: r["t_step_us"])
        for r in st:
            f = dt / (1e-6 * r["t_step_us"]) if dt else math.nan
            rtf.append(f)
            md.append("| %s | %g | %s | %s | %s | %.0f | %.0f | %.3f |" % (
                scene, dt or math.nan, r["config"], r["eliminator"], r["force"], r["t_step_us"], 1e6 / r["t_step_us"], f))
    verdict = ("supported" if rtf and min(rtf) >= 1 else "partly supported" if any(f >= 1 for f in rtf)
               else "not supported")
    md += ["", "**Verdict (real time): %s** at these resolutions — real-time factors %.3f to %.3f: the springs' "
           "forces and the integration take most of a step whichever detection is used." % (
               verdict, min(rtf) if rtf else math.nan, max(rtf) if rtf else math.nan), ""]
    macros = [("ClaimRTVerdict", verdict), ("ClaimRTMin", "%.3f" % (min(rtf) if rtf else math.nan)),
              ("ClaimRTMax", "%.3f" % (max(rtf) if rtf else math.nan))]
    return Verdict("realtime", verdict, md, macros)
