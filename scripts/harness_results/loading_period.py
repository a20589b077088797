"""A scene's loading period and rho's normalisation over it (rules.py, "stable"): the steps until a
bundled scene's forcing ends (forcing_end, forcing_end_of: core/run/window.cpp forcing_end_step), its
window, and a study row's rho converted between the input power over the loading period (the
harness's rule) and over the whole time before the window (the old normalisation: renormalised_rho).
rules.py re-exports these names."""

import math

from . import reader


def scene_window(scene):
    """A bundled scene's time.window (default 1000)."""
    try:
        return int((reader.bundled_scene(scene).get("time") or {}).get("window", 1000))
    except (OSError, ValueError):
        return 1000


def forcing_end(scene):
    """The last forced step of a bundled scene (core/run/window.cpp forcing_end_step: a moving
    driver's to_step, a load's or a pressure's ramp), None when unknown (a scene not bundled, a
    driver that never stops)."""
    try:
        sc = reader.bundled_scene(scene)
    except (OSError, ValueError):
        return None
    return forcing_end_of(sc)


def forcing_end_of(sc):
    """forcing_end of a scene document (a dict: a bundled scene or a run's resolved scene), None
    for a moving driver that never stops."""
    end = 0
    for b in sc.get("bodies", []):
        for d in b.get("drivers") or []:
            if any(v != 0 for v in d.get("velocity", [0, 0, 0])):
                if int(d.get("to_step", -1)) < 0:
                    return None
                end = max(end, int(d["to_step"]))
        for l in b.get("loads") or []:
            end = max(end, int(l.get("ramp_steps", 0)))
        p = b.get("pressure")
        if p and p.get("from") != p.get("to"):
            end = max(end, int(p.get("ramp_steps", 0)))
    return end


def loading_rho(row, rho):
    """A study row's rho over its scene's loading period (the harness's rule: renormalised_rho)."""
    return renormalised_rho(row, rho, "loading")


def renormalised_rho(row, rho, norm):
    """A study row's rho with its input power over `norm`: "loading", its scene's loading period (the
    harness's rule), or "before", the whole time before its window (the rule the first studies were
    run under, with the limits as they were calibrated for it: for a forced bundled scene rho
    (from - 1) / forcing_end, from = max(steps - window + 1, forcing_end + 1)). Converted where the
    row records its steps and rho_norm and its scene is bundled and forced; else rho as recorded
    (said in robustness.NOT_VARIED)."""
    recorded = row.get("rho_norm") or ""
    recorded = "loading" if recorded == "loading" else ("before" if recorded.startswith("before") else "")
    if recorded == norm:
        return rho
    steps = reader.num(row.get("steps"))
    f = forcing_end(row.get("scene") or "")
    if math.isnan(rho) or not reader.present(steps) or f is None:
        return rho
    # a run at dt / k (the regime study's dt/8: its dt_divide) counts k times the scene's steps for
    # its forcing and its window
    k = reader.num(row.get("dt_divide"), 1.0)
    k = 1.0 if math.isnan(k) or k <= 0 else k
    f, window = f * k, scene_window(row["scene"]) * k
    start = max(steps - window + 1, f + 1)
    if start <= 1 or steps <= f:
        return rho
    # forced: over the loading period f; unforced: over the window (the old rule: start - 1 steps)
    ratio = (f if f > 0 else min(window, steps)) / (start - 1)
    if norm == "loading" and recorded in ("", "before"):
        return rho * ratio
    if norm == "before" and recorded == "loading":
        return rho / ratio
    return rho
