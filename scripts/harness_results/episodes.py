"""A run's penetration episodes (penetration_episodes.csv: a node truly penetrating on consecutive
measured steps), per body, against claim (b)'s three criteria (their values: judge/choices.py):
  separate points   the share of the body's nodes penetrating at the peak (CGAL, measured steps);
  several steps     the 90th percentile of the episode length (nearest rank);
  eliminated        the share of episodes that failed: still open when the run ends, or ended on the
                    far side of the other body (tunnelled: gone through, not eliminated).
Lengths are measured every references.every steps: an episode that enters and leaves the same side
between two measured steps is not seen (one that goes through is)."""

import math

from . import reader

SEPARATE_MAX_FRACTION = 0.05
P90_MAX_STEPS = 100
OPEN_MAX_FRACTION = 0.05


def nearest_rank(sorted_vals, q):
    """Nearest-rank percentile q in (0, 100] of an ascending list (an observed value)."""
    if not sorted_vals:
        return None
    k = max(1, int(math.ceil(q / 100.0 * len(sorted_vals))))
    return sorted_vals[k - 1]


def failing_criteria(peak_frac, p90, failed_frac, p90_max=P90_MAX_STEPS, failed_max=OPEN_MAX_FRACTION,
                     peak_max=SEPARATE_MAX_FRACTION, unit="steps"):
    """The criteria a body's episodes fail, in words ([] when all three hold): the peak share of its
    nodes, the 90th percentile length (in `unit`; none or NaN: not judged), the failed share."""
    reasons = []
    if peak_frac is not None and peak_frac == peak_frac and peak_frac > peak_max:
        reasons.append("peak %.1f %% of its nodes > %g %%" % (100 * peak_frac, 100 * peak_max))
    if p90 is not None and p90 == p90 and p90 > p90_max:
        reasons.append("p90 %s %s > %d" % ("%d" % p90 if isinstance(p90, int) else "%g" % p90, unit, p90_max))
    if failed_frac > failed_max:
        reasons.append("%.1f %% failed (open or through) > %g %%" % (100 * failed_frac, 100 * failed_max))
    return reasons


def episode_stats(episodes, body, nodes, peak):
    """The episodes of one body in one run against the three criteria."""
    lengths = sorted(int(r["steps"]) for r in episodes if r["body"] == body)
    n = len(lengths)
    nopen = sum(int(r["open"]) for r in episodes if r["body"] == body)
    nthrough = sum(int(r["tunnelled"]) for r in episodes if r["body"] == body)
    failed = sum(1 for r in episodes if r["body"] == body and (r["open"] or r["tunnelled"]))
    st = {"episodes": n, "median": nearest_rank(lengths, 50), "p90": nearest_rank(lengths, 90),
          "max": lengths[-1] if lengths else None, "open": nopen, "through": nthrough,
          "open_frac": (failed / n) if n else 0.0, "through_frac": (nthrough / n) if n else 0.0,
          "passages": any(r.get("passages") for r in episodes),
          "peak": peak, "peak_frac": (peak / nodes) if nodes else None}
    reasons = failing_criteria(st["peak_frac"], st["p90"], st["open_frac"])
    st["holds"] = not reasons
    st["why"] = "; ".join(reasons) if reasons else "all three met"
    return st


_FIGURES = {}


def run_figures(path):
    """(summary, guest stats, host stats) of the run in `path`, read once."""
    if path not in _FIGURES:
        s = reader.load_summary(path)
        host, guest = reader.contact_bodies(s, strict=False)
        cols = reader.load_columns(path, ["step", "true_pen_guest", "true_pen_host"])
        _, g = reader.measured(cols, "true_pen_guest")
        _, h = reader.measured(cols, "true_pen_host")
        ep = reader.load_episodes(path)
        gs = episode_stats(ep, guest, reader.body_nodes(s, guest), int(max(g, default=0)))
        gs["tunnelled"] = reader.num(reader.window_figures(s).get("tunnelled"), 0.0)
        _FIGURES[path] = (s, gs, episode_stats(ep, host, reader.body_nodes(s, host), int(max(h, default=0))))
    return _FIGURES[path]
