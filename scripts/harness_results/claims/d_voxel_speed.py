"""Claim (d), section 3: "collision search using space voxelization is one of the most fast". On
results/accuracy_time.csv, at equal error: per scenario, the voxel model's most accurate stable
setting (its error e_v), and per exact detector the fastest stable setting with pos_err_max <= e_v
(none: the detector is not comparable at that error, and the voxel model is faster at its own error
only by being less accurate); also the smallest error each reaches. Verdict: supported when the voxel
model is the fastest at equal error in every scenario, partly when it is the fastest only at errors
the exact detectors beat, not supported otherwise.
"""

import math

from .c_restrictions import accuracy_rows
from .common import EXACT, SCENE_ORDER, Verdict


def per_scene(rows):
    """The voxel model against the exact detectors at equal error, per scenario."""
    out = []
    for scene in SCENE_ORDER:
        st = [r for r in rows if r["scene"] == scene and r["stable"] == "yes" and not math.isnan(r["pos_err_max_mm"])]
        vox = [r for r in st if r["detector"] == "voxel"]
        if not vox:
            continue
        best = min(vox, key=lambda r: (r["pos_err_max_mm"], r["t_contact_us"]))
        row = dict(scene=scene, voxel=best, exact={})
        for det in EXACT:
            d = [r for r in st if r["detector"] == det]
            at = [r for r in d if r["pos_err_max_mm"] <= best["pos_err_max_mm"]]
            row["exact"][det] = dict(
                fastest_at=min(at, key=lambda r: r["t_contact_us"]) if at else None,
                best=min(d, key=lambda r: (r["pos_err_max_mm"], r["t_contact_us"])) if d else None)
        faster = [e["fastest_at"]["t_contact_us"] / best["t_contact_us"] for e in row["exact"].values() if e["fastest_at"]]
        row["fastest"] = all(x > 1.0 for x in faster) if faster else None
        bests = [e["best"]["pos_err_max_mm"] for e in row["exact"].values() if e["best"]]
        row["beaten"] = bool(bests) and min(bests) < best["pos_err_max_mm"]
        out.append(row)
    if not out:
        return out, "not tested (no stable voxel setting)"
    if all(r["fastest"] and not r["beaten"] for r in out):
        verdict = "supported"
    elif all(r["fastest"] is not False for r in out):
        verdict = "partly supported"
    else:
        verdict = "not supported"
    return out, verdict


def judge(ctx):
    rows = accuracy_rows(ctx)
    if not rows:
        return Verdict("d_voxel_speed", "not tested")  # said once, in (c)'s section
    ds, verdict = per_scene(rows)
    md = ["## (d) Space voxelization is one of the fastest collision searches", "",
          "At equal error: per scenario the voxel model's most accurate stable setting, and per exact detector the "
          "fastest stable setting at least as accurate (none: no stable setting of that detector is), and the "
          "smallest error it reaches. Time: detection + elimination, µs per step.", "",
          "| scenario | voxel setting | voxel pos. error (mm) | voxel time (µs) | detector | fastest at <= voxel error "
          "| its error (mm) | its time (µs) | times the voxel time | smallest error (mm) |",
          "|---|---|---:|---:|---|---|---:|---:|---:|---:|"]
    for r in ds:
        v = r["voxel"]
        for det, e in r["exact"].items():
            f = e["fastest_at"]
            md.append("| %s | %s %s %s | %.3g | %.1f | %s | %s | %s | %s | %s | %s |" % (
                r["scene"], v["config"], v["eliminator"], v["force"], v["pos_err_max_mm"], v["t_contact_us"], det,
                "%s %s" % (f["eliminator"], f["force"]) if f else "none stable",
                "%.3g" % f["pos_err_max_mm"] if f else "", "%.0f" % f["t_contact_us"] if f else "",
                "%.1f" % (f["t_contact_us"] / v["t_contact_us"]) if f else "",
                "%.3g" % e["best"]["pos_err_max_mm"] if e["best"] else "no stable setting"))
    speed = [min(e["fastest_at"]["t_contact_us"] for e in r["exact"].values() if e["fastest_at"]) / r["voxel"]["t_contact_us"]
             for r in ds if any(e["fastest_at"] for e in r["exact"].values())]
    acc = [r["voxel"]["pos_err_max_mm"] / min(e["best"]["pos_err_max_mm"] for e in r["exact"].values() if e["best"])
           for r in ds if any(e["best"] for e in r["exact"].values())]
    md += ["", "**Verdict (d): %s** — the voxel model is the fastest at its own error in %d of %d scenarios (the "
           "fastest exact detector at that error takes %.0f to %.0f times longer), but in %d of %d scenarios an "
           "exact detector reaches an error %.1f to %.0f times smaller, which no voxel setting reaches: it is fast "
           "by being less accurate, not at equal error." % (
               verdict, sum(1 for r in ds if r["fastest"]), len(ds), min(speed) if speed else math.nan,
               max(speed) if speed else math.nan, sum(1 for r in ds if r["beaten"]), len(ds),
               min(acc) if acc else math.nan, max(acc) if acc else math.nan), ""]
    macros = [("ClaimDVerdict", verdict), ("ClaimDSpeedMin", "%.0f" % (min(speed) if speed else math.nan)),
              ("ClaimDSpeedMax", "%.0f" % (max(speed) if speed else math.nan)),
              ("ClaimDAccMin", "%.1f" % (min(acc) if acc else math.nan)),
              ("ClaimDAccMax", "%.0f" % (max(acc) if acc else math.nan))]
    return Verdict("d_voxel_speed", verdict, md, macros, data=ds)
