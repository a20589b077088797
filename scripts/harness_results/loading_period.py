"""A scene's loading period: the steps until a bundled scene's forcing ends (forcing_end,
forcing_end_of: core/run/window.cpp forcing_end_step) and its window. rules.py re-exports these names."""

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
