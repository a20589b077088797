"""A finished run judged again over another final window, or against its second reference, from
what it wrote: the window's length is a choice of the rule (issue: verdicts robust to the rule's
choices), and so is the kind of reference a method is judged against.

rewindow(folder, s, factor) returns a copy of the run's summary `s` whose window (core/run/window.hpp:
span, contact power, rho, kinetic growth, kick, the verdict) and window statistics of the errors
(error_vs_reference and error_vs_reference_also: pos_err_max, pos_err_rms, gap_max, gap_mean; the
pair's depth_max and tunnelled) are those of a window `factor` times the scene's time.window steps,
computed from folder/steps.csv exactly as the harness computes them (judge_stability, Series::over).
At factor 1 it reproduces the summary's own figures (tests/scripts/test_rewindow.py). A run that
settled keeps "settled" over any window (the settle test is not a window figure).

also_reference(s) returns a copy whose error_vs_reference is the second reference's (harness run
--compare-also): the depth and tunnelled figures, which do not depend on the reference, kept.
"""

import copy
import math

from . import reader

# core/run/window.hpp
INJECTION_RATIO = 0.02
GROWTH_FACTOR = 2.0
KICK_SHARE = 0.1


def _stat(values):
    """WindowStat of a list (n, mean, max, min, amplitude); {} without values."""
    if not values:
        return {"measured_steps": 0, "mean": None, "max": None, "min": None, "amplitude": None}
    mx, mn = max(values), min(values)
    return {"measured_steps": len(values), "mean": sum(values) / len(values), "max": mx, "min": mn,
            "amplitude": mx - mn}


def _column(cols, key):
    return cols.get(key) or [math.nan] * len(cols["step"])


def span(s, window_steps):
    """(from, to, forcing_end, after_forcing) of a window of `window_steps` steps (window_span)."""
    w = reader.window(s)
    to = int(reader.num(w.get("to_step"), reader.steps_run(s)))
    forcing = reader.num(w.get("forcing_ends_step"), 0)
    forcing = int(forcing) if reader.present(forcing) else 0
    after = bool(w.get("after_forcing", True))
    frm = max(1, to - max(1, int(window_steps)) + 1)
    if after:
        frm = max(frm, forcing + 1)
    return frm, to, forcing, after


def scene_window(s):
    """The run's time.window steps (its resolved scene; 1000 when it does not say)."""
    t = ((s.get("resolved_scene") or {}).get("time") or {})
    return int(reader.num(t.get("window"), 1000))


def rewindow(folder, s, factor, cols=None, recompute=False):
    """The summary of the run in `folder` judged over a window of `factor` x its scene's window
    (see the module's docstring). `cols`: its steps.csv already read (reader.load_steps).
    `recompute`: at factor 1 too (the test that it reproduces the harness's figures)."""
    out = copy.deepcopy(s)
    if factor == 1 and not recompute:
        return out
    cols = cols if cols is not None else reader.load_steps(folder)
    if "pair" in cols and cols["pair"] and isinstance(cols["pair"][0], str):
        keep = [i for i, p in enumerate(cols["pair"]) if p == cols["pair"][0]]
        cols = {k: [v[i] for i in keep] for k, v in cols.items()}
    steps = [int(x) for x in cols["step"]]
    frm, to, forcing, after = span(s, round(factor * scene_window(s)))
    w = out.setdefault("window", {})
    w.update({"from_step": frm, "to_step": to, "steps": to - frm + 1})
    idx = {st: i for i, st in enumerate(steps)}
    inside = [i for i, st in enumerate(steps) if frm <= st <= to]

    def series(key):
        col = _column(cols, key)
        return [col[i] for i in inside if reader.present(col[i])]

    # the errors' window statistics (Series::over over the measured steps in the span)
    for p_i, p in enumerate(out.get("pairs") or []):
        if p_i:
            break  # steps.csv rows of the first pair only (the studies' scenes have one)
        for key in ("error_vs_reference", "error_vs_reference_also"):
            e = p.get(key)
            if not e:
                continue
            # steps.csv's columns of each reference (also_reference swaps the two)
            swapped = bool(out.get("_also_first"))
            prefix = "" if (key == "error_vs_reference") != swapped else "also_"
            ew = e.setdefault("window", {})
            for fig in ("pos_err_max", "pos_err_rms", "gap_max", "gap_mean"):
                col = prefix + fig
                if col in cols:
                    ew[fig] = _stat(series(col))
            if key == "error_vs_reference":
                if "max_depth" in cols:
                    ew["depth_max"] = _stat(series("max_depth"))
                if "tunnelled_guest" in cols:
                    g, h = _column(cols, "tunnelled_guest"), _column(cols, "tunnelled_host")
                    ew["tunnelled"] = _stat([g[i] + (h[i] if reader.present(h[i]) else 0.0) for i in inside
                                             if reader.present(g[i])])
    # stability (judge_stability)
    dt = reader.num(((s.get("resolved_scene") or {}).get("time") or {}).get("dt"))
    if not (reader.present(dt) and frm in idx and to in idx and "work_contact" in cols):
        return out
    wc, we = _column(cols, "work_contact"), _column(cols, "work_external")
    ke, el, res = _column(cols, "energy_kinetic"), _column(cols, "energy_elastic"), _column(cols, "residual")
    i_to = idx[to]
    before_wc = wc[idx[frm - 1]] if frm > 1 and (frm - 1) in idx else 0.0
    before_we = we[idx[frm - 1]] if frm > 1 and (frm - 1) in idx else 0.0
    T = (to - frm + 1) * dt
    t_in = T
    if forcing > 0 and frm > 1:
        t_in = forcing * dt if after else (frm - 1) * dt
    pc = (wc[i_to] - before_wc) / T
    e0 = reader.num((s.get("energy") or {}).get("energy_initial"), 0.0)
    e_in = e0 + max(0.0, before_we)
    p_in = e_in / t_in if e_in > 0 else (el[i_to] / T if reader.present(el[i_to]) else math.nan)
    rho = pc / p_in if p_in and p_in > 0 else (math.inf if pc > 0 else 0.0)
    kin = [ke[i] for i in inside]
    kinetic = _stat(kin)
    scale = max(e_in, el[i_to] if reader.present(el[i_to]) else 0.0)
    kicked = wc[i_to] > KICK_SHARE * scale and kinetic["mean"] > KICK_SHARE * scale
    mid = frm + (to - frm + 1) // 2
    first = max([ke[idx[st]] for st in range(frm, mid) if st in idx] or [0.0])
    second = max([ke[idx[st]] for st in range(mid, to + 1) if st in idx] or [0.0])
    growth = second / first if first > 0 else (math.inf if second > 0 else 1.0)
    negligible = 1e-9 * max(scale, 1e-300)
    if s.get("settled"):
        verdict = "settled"
    elif not after:
        verdict = "forced"
    elif rho > INJECTION_RATIO or kicked:
        verdict = "injects"
    elif growth > GROWTH_FACTOR and second > negligible and to - frm >= 10:
        verdict = "grows"
    else:
        verdict = "chatters"
    w.update({"contact_power_W": pc, "input_power_W": p_in, "input_period_s": t_in, "contact_power_ratio": rho,
              "energy_in_J": e_in, "energy_scale_J": scale, "kicked": kicked, "kinetic_growth": growth,
              "kinetic_energy": kinetic, "residual": _stat([res[i] for i in inside if reader.present(res[i])]),
              "window_factor": factor})
    if s.get("stability_verdict") in ("settled", "chatters", "injects", "grows", "forced"):
        out["stability_verdict"] = verdict  # a run that failed keeps its own
    return out


def also_reference(s):
    """A copy of summary `s` judged against its second reference (--compare-also), None when it has
    none: error_vs_reference's position and gap figures replaced by error_vs_reference_also's."""
    out = copy.deepcopy(s)
    any_also = False
    figs = ("pos_err_max", "pos_err_rms", "gap_max", "gap_mean")
    for p in out.get("pairs") or []:
        also = p.get("error_vs_reference_also")
        if not also:
            continue
        any_also = True
        e = p.setdefault("error_vs_reference", {})
        first = {f: e.get(f) for f in figs + ("touching_nodes",)}
        first_w = {f: (e.get("window") or {}).get(f) for f in figs}
        for fig in figs + ("touching_nodes",):
            e[fig] = also.get(fig)
        ew, aw = e.setdefault("window", {}), also.get("window") or {}
        for fig in figs:
            ew[fig] = aw.get(fig)
        p["error_vs_reference_also"] = dict(first, dir=(s.get("compare") or {}).get("dir"), window=first_w)
    if not any_also:
        return None
    out["compare"] = dict(out.get("compare") or {}, dir=(s["pairs"][0].get("error_vs_reference_also") or {}).get("dir"))
    out["_also_first"] = not s.get("_also_first")  # steps.csv's also_ columns are now the first's (rewindow)
    return out
