"""Measure a run: from one row of a study's CSV file (or a run's summary), whether it failed and why,
its stability class, and its error and time with their intervals. Nothing here compares two runs.

A run fails when it blew up (the study recorded it failed: a state not finite, a guard violation,
an error), when it lets a node through the other body (more than Spec.tunnel_limit over the final
window: a guest node through the host for any method, a host node through the guest for a method that
acts both ways; a one-sided method's host nodes through are reported beside, nodes_through), or, with
Spec.unstable_fails, when it is unstable.

Its stability class is the C++ class (core/run/window.hpp) where the row records it (a column
`stability_class`, written by the studies from summary.json's stability_verdict since that class),
decided again from the figures it was decided on where the row records them too (run_class: the
chatter length and the injection share are choices of the specification);
the committed studies' rows were made before it and record the error's motion over the window
instead, so for them the class is read from that motion alone: "chatters" when the largest
position error moves by more than the stated length L over the window (L as Spec.chatter_length says),
else "steady" (the class's energy terms are not in those rows; the table says "from the error's
motion" where this is so).

An error's interval: its range over the final window (window minimum to maximum of pos_err_max;
where a row records only the mean and the chatter amplitude, the mean minus and plus the amplitude,
which contains that range) widened on both sides by the floor of the reference it is measured
against (Spec.floor). A time's interval: the range over the study's repeats (t_*_min_us to
t_*_max_us).

Where the ensemble study ran the row again as an ensemble (results/ensembles.csv: members that
differ only by node order and a jitter far below the mesh's precision), the error's interval spans
every member's window range, and the class is the members': a run fails when most of its members
are unstable or any lets a node through; a class that differs between members reads `flips`.
"""

import math
import os

from .. import reader

UNSTABLE = ("chatters", "injects", "grows")
GRID_DETECTORS = ("voxel", "voxel_exact", "distance_field")
OUTPUTS_PAGE = os.path.join(reader.SOURCE, "docs", "outputs.md")


def stability_thresholds(path=OUTPUTS_PAGE):
    """{name: value} of the C++ stability class's thresholds (core/run/window.hpp kStabilityThresholds),
    read from the page the harness generates from them (docs/outputs.md, "Stability thresholds"),
    not copied."""
    out, inside = {}, False
    with open(path) as f:
        for line in f:
            if line.startswith("## "):
                inside = line.strip() == "## Stability thresholds"
            elif inside and line.startswith("| `"):
                cells = [c.strip() for c in line.strip().strip("|").split("|")]
                out[cells[0].strip("`")] = float(cells[1])
    if "edge_share" not in out:
        raise ValueError("%s: no Stability thresholds table with edge_share (run harness outputs)" % path)
    return out


# The C++ class's length without a voxel or floor: this share of the node spacing (kEdgeShare).
THRESHOLDS = stability_thresholds()
EDGE_SHARE = THRESHOLDS["edge_share"]
GROWTH_FACTOR = THRESHOLDS["growth_factor"]


class Scenes:
    """What the judge knows of each scene from the committed references: the floor of each
    reference (mm) and the node spacing of its surfaces at rest (mm)."""

    def __init__(self, root):
        self.root = root
        self._floor, self._spacing = {}, {}
        self.ensembles = []  # results/ensembles.csv's rows (judge.claims.Data reads them)
        self.edge = {}  # scene: the stated edge-share chatter length, mm (judge.claims.Data fills it)

    def ensemble_of(self, row):
        """The ensemble study's row for a study row (same file and configuration), None without one.
        The keys are made once: every specification measures the same rows."""
        if getattr(self, "_ens_of", None) is None or self._ens_of[0] is not self.ensembles:
            by = {}
            for e in self.ensembles:
                by.setdefault(ensemble_key(e, row_file=e.get("file")), e)
            self._ens_of = (self.ensembles, by, {})
        _, by, rows = self._ens_of
        if id(row) not in rows:
            rows[id(row)] = (row, by.get(ensemble_key(row)))
        return rows[id(row)][1]

    def floor_mm(self, scene, kind):
        """The floor of the reference a row of `kind` ("one-sided" or "both ways") is measured against."""
        name = scene + ("_one_sided" if kind == "one-sided" else "")
        if name not in self._floor:
            self._floor[name] = reader.reference_floor_mm(self.root, name)
        return self._floor[name]

    def stated_edge_mm(self, scene):
        """The chatter length the C++ class states for the scene where no voxel or floor sets it (a
        quarter of the mean spring length of the bodies in contact: the accuracy study's rows with
        chatter_length_from "edge share"), NaN where no row states it."""
        return self.edge.get(scene, math.nan)

    def mesh_floor_mm(self):
        """The spheres' refined reference against its own (references_differences.csv), NaN without it."""
        rows = reader.read_csv(os.path.join(self.root, "references_differences.csv"), numbers=("difference_mm",),
                               missing=[])
        return next((r["difference_mm"] for r in rows if "refined" in r["comparison"]), math.nan)

    def spacing_mm(self, scene):
        """The median distance from a surface node to its nearest neighbour at rest, averaged over the
        bodies of the scene's reference (NaN without one): the stand-in for the mean spring length."""
        if scene not in self._spacing:
            self._spacing[scene] = _spacing(os.path.join(self.root, "references", scene, "surfaces.csv"))
        return self._spacing[scene]


def _spacing(path):
    import numpy as np
    if not os.path.exists(path):
        return math.nan
    rows = reader.read_csv(path, numbers=("x0", "y0", "z0"), text=("body",))
    per_body = []
    for body in sorted({r["body"] for r in rows}):
        p = np.array([[r["x0"], r["y0"], r["z0"]] for r in rows if r["body"] == body])
        if len(p) < 2:
            continue
        best = np.full(len(p), np.inf)
        for i in range(0, len(p), 512):
            d = np.linalg.norm(p[i:i + 512, None, :] - p[None, :, :], axis=2)
            d[d == 0] = np.inf
            best[i:i + 512] = d.min(axis=1)
        per_body.append(float(np.median(best)))
    return 1e3 * float(np.mean(per_body)) if per_body else math.nan


class Run:
    """One measured run. label: how tables name it; failed: why it failed ('' when it did not);
    cls: its stability class; cls_from: 'run' (the C++ class) or 'error motion' (the stand-in);
    err, err_lo, err_hi (mm; NaN without a reference); t, t_lo, t_hi (µs per step; NaN when untimed)."""

    def __init__(self, row, label, failed, cls, cls_from, err, err_lo, err_hi, t, t_lo, t_hi, length,
                 host_beside=0.0):
        self.row, self.label, self.failed, self.cls, self.cls_from = row, label, failed, cls, cls_from
        self.host_beside = host_beside  # a one-sided method's host nodes through the guest (not a failure)
        self.err, self.err_lo, self.err_hi = err, err_lo, err_hi
        self.t, self.t_lo, self.t_hi = t, t_lo, t_hi
        self.length = length

    def __repr__(self):
        return "Run(%r, err=%.3g, failed=%r)" % (self.label, self.err, self.failed)


KEY_COLUMNS = ("scene", "config", "detector", "eliminator", "response", "force", "voxel_mm", "two_sided", "regime")


def ensemble_key(row, row_file=None):
    """What identifies a configuration across the study files and results/ensembles.csv."""
    def cell(k):
        v = row.get(k)
        if k == "voxel_mm":
            v = reader.num(v)
            return "" if v != v else "%.6g" % v
        return "" if v is None or v != v else str(v)
    return (row_file or row.get("_file", ""),) + tuple(cell(k) for k in KEY_COLUMNS)


def num(row, key):
    return reader.num(row.get(key))


SCALE = {"stated": 1.0, "half": 0.5, "double": 2.0}


def chatter_length(row, scene, kind, scenes, spec):
    """L in mm for a row made before the C++ class: the larger of a grid detector's voxel (not with
    spec.chatter_length "edge"), the reference's floor and EDGE_SHARE of the node spacing, times
    the choice's scale."""
    parts = [EDGE_SHARE * scenes.spacing_mm(scene), scenes.floor_mm(scene, kind)]
    if spec.chatter_length != "edge" and (row.get("detector") in GRID_DETECTORS or (
            row.get("detector") is None and reader.present(row.get("voxel_mm")))):
        parts.append(num(row, "voxel_mm"))
    parts = [p for p in parts if p == p]
    return SCALE.get(spec.chatter_length, 1.0) * max(parts) if parts else math.nan


def run_class(row, spec, scenes):
    """(class, L mm) of a row that records its C++ class: the class again from the figures it was
    decided on (the row's chatter_amp_mm, chatter_length_mm, injection_share, kinetic_growth,
    kinetic_max_J, growth_floor_J, reader.class_figures) under spec's chatter_length and
    contact_input_share, the rules' order as in core/run/window.hpp (injects, grows, chatters, steady);
    the class as recorded where the row lacks those figures or the class is settled, forced or failed.
    Growth is read from the window's largest kinetic energy, which bounds its second half's: a run the
    C++ called grows stays so unless it injects. Under the choices as written the class is the run's."""
    cls = row["stability_class"]
    length = num(row, "chatter_length_mm")
    if cls not in UNSTABLE + ("steady",) or not reader.present(row.get("chatter_length_from")):
        return cls, length
    if spec.chatter_length == "edge":
        edge = scenes.stated_edge_mm(row.get("scene", "")) if hasattr(scenes, "stated_edge_mm") else math.nan
        length = edge if edge == edge else length
    else:
        length *= SCALE[spec.chatter_length]
    inj, amp = num(row, "injection_share"), num(row, "chatter_amp_mm")
    if inj == inj and inj > spec.contact_input_share:
        return "injects", length
    growth, ke, floor = num(row, "kinetic_growth"), num(row, "kinetic_max_J"), num(row, "growth_floor_J")
    if cls == "grows" or (cls == "injects" and growth > GROWTH_FACTOR and ke > floor):
        return "grows", length
    if amp == amp and amp > length:
        return "chatters", length
    return "steady", length


def one_sided(row):
    """Whether the row's method acts on the guest alone: its `two_sided` column says no, or it is the
    paper's grid (voxel, voxel_exact) with line or plane and the row does not say (regime.csv,
    the report's runs record no two_sided column: the grid's responses push the guest only)."""
    ts = row.get("two_sided")
    if ts in ("yes", "no"):
        return ts == "no"
    return row.get("detector") in ("voxel", "voxel_exact") and row.get("eliminator") in ("line", "plane")


def nodes_through(row):
    """(the nodes through that fail the run, a one-sided method's host nodes reported beside). The
    window's largest count (column tunnelled, guest and host together) fails a method that acts both
    ways. For a one-sided method whose row records the count by body at the end (tunnelled_guest,
    tunnelled_host), the guest's count fails it: the larger of the guest's at the end and the window's
    largest less the host's at the end (a count that fell in the window is laid on the guest); its host
    nodes are reported beside. A row without the split keeps the count together (fails on either)."""
    total = num(row, "tunnelled")
    g, h = num(row, "tunnelled_guest"), num(row, "tunnelled_host")
    if not (one_sided(row) and g == g and h == h):
        return total, 0.0
    through = max(g, total - h) if total == total else g
    return through, h


def measure(row, spec, scenes, label="", kind=None, time_key="t_contact"):
    """A Run from a study row. kind: the reference's kind (default the row's `reference` column,
    else both ways); time_key: the time column's stem (t_contact or t_step)."""
    scene = row.get("scene", "")
    kind = kind or row.get("reference") or "both ways"
    err = num(row, "pos_err_max_mm")
    amp = num(row, "pos_err_amp_mm")
    top = num(row, "pos_err_max_max_mm")
    if top == top:
        low = top - amp if amp == amp else err
    else:
        top = err + (amp if amp == amp else 0.0)
        low = err - (amp if amp == amp else 0.0)
    floor = scenes.floor_mm(scene, kind)
    floor = 0.0 if floor != floor else floor
    if spec.floor == "double":
        floor *= 2
    elif spec.floor == "mesh":
        mesh = scenes.mesh_floor_mm()
        floor = max(floor, mesh) if mesh == mesh else floor
    length = chatter_length(row, scene, kind, scenes, spec)
    ens = scenes.ensemble_of(row) if getattr(scenes, "ensemble_of", None) else None
    if ens is not None:
        return measure_ensemble(row, ens, spec, label, floor, length, time_key)
    if reader.present(row.get("stability_class")):
        cls, stated = run_class(row, spec, scenes)
        cls_from = "run" if cls == row["stability_class"] else "run's figures"
        length = stated if stated == stated else length
    elif row.get("stability") == "failed" or row.get("status") == "error":
        cls, cls_from = "failed", "run"
    else:
        cls = "chatters" if (amp == amp and length == length and amp > length) else "steady"
        cls_from = "error motion"
    tunnelled, host_beside = nodes_through(row)
    failed = ""
    if cls == "failed":
        failed = "blew up or failed (%s)" % (row.get("why_unstable") or "status error")
    elif tunnelled == tunnelled and tunnelled > spec.tunnel_limit:
        failed = "%d nodes through" % tunnelled
    elif cls == "forced":
        failed = "ended before its loading did"
    elif spec.unstable_fails and cls in UNSTABLE:
        failed = cls
        if cls_from == "error motion":
            failed += " (%.2g mm > %.2g mm)" % (amp, length)
        elif cls_from == "run's figures" and cls == "chatters":
            failed += " (%.2g mm > %.2g mm)" % (num(row, "chatter_amp_mm"), length)
        elif cls_from == "run's figures" and cls == "injects":
            failed += " (%.2g > %.2g)" % (num(row, "injection_share"), spec.contact_input_share)
    t = num(row, time_key + "_us")
    t_lo, t_hi = num(row, time_key + "_min_us"), num(row, time_key + "_max_us")
    if t == t and not t_lo == t_lo:
        t_lo = t_hi = t
    return Run(row, label, failed, cls, cls_from, err, max(0.0, low - floor), top + floor, t, t_lo, t_hi, length,
               host_beside)


def measure_ensemble(row, ens, spec, label, floor, length, time_key):
    """A Run from a row that the ensemble study ran again (`ens`: its results/ensembles.csv row)."""
    members = int(reader.num(ens.get("members"), 1))
    classes = {}
    for part in str(ens.get("classes") or "").split(";"):
        if ":" in part:
            k, n = part.split(":")
            classes[k] = int(n)
    unstable = sum(n for k, n in classes.items() if k in UNSTABLE)
    cls = ens.get("stability_verdict") or "failed"
    # the nodes through: the members' largest; a one-sided method's the guest's where the file records
    # them by body (nodes_through, on the members' largest counts)
    tunnelled, host_beside = nodes_through(dict(row, tunnelled=ens.get("tunnelled_max"),
                                                tunnelled_guest=ens.get("tunnelled_guest_max"),
                                                tunnelled_host=ens.get("tunnelled_host_max")))
    failed = ""
    if int(reader.num(ens.get("failed_members"), 0)):
        failed = "blew up or failed in %d of %d members" % (int(reader.num(ens.get("failed_members"))), members)
    elif tunnelled == tunnelled and tunnelled > spec.tunnel_limit:
        failed = "%d nodes through" % tunnelled
    elif classes.get("forced"):
        failed = "ended before its loading did"
    elif spec.unstable_fails and unstable * 2 > members:
        failed = "unstable in %d of %d members" % (unstable, members)
    err = reader.num(ens.get("pos_err_max_mm"))
    lo, hi = reader.num(ens.get("pos_err_max_min_mm")), reader.num(ens.get("pos_err_max_max_mm"))
    t = num(row, time_key + "_us")
    t_lo, t_hi = num(row, time_key + "_min_us"), num(row, time_key + "_max_us")
    if t == t and not t_lo == t_lo:
        t_lo = t_hi = t
    return Run(row, label, failed, cls, "ensemble of %d" % members, err, max(0.0, lo - floor), hi + floor,
               t, t_lo, t_hi, length, host_beside)


def is_constant(force):
    """A constant force ("F=0.003"; not "F=0", no force at all)."""
    return isinstance(force, str) and force.startswith("F=") and reader.num(force[2:]) > 0


def force_pool(force, spec):
    """Whether a row of the paper's model with this force enters a claim's pool."""
    return is_constant(force) or (force == "auto" and spec.auto_force == "pooled")
