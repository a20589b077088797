"""Claim (a) against the reference solution: the runs of claim (a) compared with the scenario's
converged reference (`--compare results/references/<scene>`). Counting penetrations rewards a
direction that pushes the bodies apart too early; here plane beats line when it is no worse on
pos_err_max and gap_max and strictly better on one. Verdict as for claim (a), over the implant
settings compared with a reference.
"""

from .. import reader, rules
from .common import Verdict

KEYS = ["pos_err_max", "gap_max"]


def ref_errors(path):
    """The run's error against the scene's reference at the end, mm; None without one."""
    e = reader.final_reference_errors(reader.load_summary(path))
    if not e:
        return None
    return {k: 1000.0 * float(e[k]) for k in ("pos_err_max", "gap_max", "depth_max")}


def compare_ref(line, plane):
    """Plane better when no worse on pos_err_max and gap_max, strictly better on one ("no reference"
    when either run has none)."""
    if line is None or plane is None:
        return "no reference"
    d = rules.dominance(line, plane, KEYS)
    return {"b better": "plane better", "a better": "line better"}.get(d, d)


def judge(ctx):
    rows = []
    for key, title, force, line_path, plane_path in ctx.pairs():
        le, pe = ref_errors(line_path), ref_errors(plane_path)
        rows.append((key, title, force, le, pe, compare_ref(le, pe)))
    implant = [r for r in rows if ctx.by[r[0]]["scene"] == "implant_expansion" and r[3] and r[4]]
    wins = sum(1 for r in implant if r[5] == "plane better")
    verdict = rules.plane_verdict(implant, wins, "not tested (no runs compared with a reference)")
    md = ["### (a) against the reference solution", "",
          "Counting penetrations rewards a direction that pushes the bodies apart too early. The same runs "
          "compared with the scenario's converged reference (`--compare results/references/<scene>`): "
          "pos. error = largest distance of a surface vertex from where the reference has it; gap = largest "
          "gap where the reference has the bodies touching. Plane beats line when it is no worse on both and "
          "strictly better on one.", "",
          "| scenario | force | line pos. error (mm) | plane pos. error (mm) | line gap (mm) | plane gap (mm) "
          "| line depth (mm) | plane depth (mm) | result |",
          "|---|---|" + "---:|" * 6 + "---|"]
    for key, title, force, l, p, res in rows:
        if l and p:
            md.append("| %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %s |" % (
                title, force, l["pos_err_max"], p["pos_err_max"], l["gap_max"], p["gap_max"], l["depth_max"],
                p["depth_max"], res))
    md += ["", "**Verdict (a) against the reference: %s** — plane better than line in %d of %d implant force "
           "settings (%s)." % (verdict, wins, len(implant), ", ".join("%s: %s" % (r[2], r[5]) for r in implant)), ""]
    macros = [("ClaimARefVerdict", verdict), ("ClaimARefWins", "%d" % wins)]
    return Verdict("a_reference", verdict, md, macros, data=rows)
