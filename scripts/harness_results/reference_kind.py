"""The two kinds of reference a method can be judged against (rules.py, "error"): a one-sided
method (only the guest's nodes pushed out of the host) against the one-sided reference, the limit
it converges to, a method both ways against the two-sided one (OF_ITS_KIND, the rule as written);
the run without contact force's figures on the kind of the row it is compared with; the floors of
the two references in the noise; a run's summary judged against its second reference
(also_reference). rules.py re-exports these names."""

import copy

from . import reader

# The reference a method is judged against: its own kind, one-sided methods
# against the one-sided reference (the limit a one-sided method converges to) and two-sided ones
# against the two-sided; the other choice judges every method against the two-sided reference.
OF_ITS_KIND = "of its kind"


def same_kind_base(row, base):
    """The run without contact force's figures against the reference of `row`'s kind (accuracy_time.csv
    records both: pos_err_max_one_sided_mm, pos_err_max_both_ways_mm); a row that does not say its
    kind is against the two-sided reference (the studies other than accuracy_time.csv measure
    against it); `base` as it is when it records one kind only."""
    kind = row.get("reference") or "both ways"
    if base is None or kind not in ("one-sided", "both ways") or (base.get("reference") or "both ways") == kind:
        return base
    v = base.get("pos_err_max_%s_mm" % kind.replace("-", "_").replace(" ", "_"))
    return dict(base, pos_err_max_mm=v) if reader.present(v) else base


def as_two_sided(base):
    """The run without contact force as the studies other than accuracy_time.csv measure it: against
    the two-sided reference (its pos_err_max_both_ways_mm where it records it; same_kind_base maps it
    back for a row of another kind)."""
    v = base.get("pos_err_max_both_ways_mm")
    if base.get("reference") in (None, "", "both ways") or not reader.present(v):
        return base
    return dict(base, pos_err_max_mm=v, reference="both ways")


class KindFloor(float):
    """The floors of the two kinds of reference (rows measured each against the reference of its
    kind: OF_ITS_KIND): as a number the larger (what a table prints); noise() takes the larger of the
    two rows' own references' floors, so two one-sided rows are judged by the one-sided reference's
    floor alone. `by`: {"one-sided": mm, "both ways": mm}."""

    def __new__(cls, by):
        vals = [v for v in by.values() if v == v]
        obj = super().__new__(cls, max(vals) if vals else float("nan"))
        obj.by = dict(by)
        return obj

    def of(self, *rows):
        """The floor of a comparison between `rows`: the largest of their references' floors (a row
        that does not say its kind is against the two-sided reference)."""
        vals = [self.by.get(r.get("reference") or "both ways", float(self)) for r in rows]
        vals = [v for v in vals if v == v]
        return max(vals) if vals else float(self)


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
    out["_also_first"] = not s.get("_also_first")
    return out


def of_its_kind(s):
    """(summary, kind): a run judged against the reference of its kind (rules.py, "error"): a
    one-sided run (contacts two_sided false, the paper's model) measured against its scene's one-sided
    reference beside (--compare-also .../<scene>_one_sided) on that one ("one-sided"); otherwise as
    its summary has it ("both ways")."""
    two = [bool((c or {}).get("two_sided")) for c in (reader.resolved(s).get("contacts") or [])]
    also = (reader.pair(s).get("error_vs_reference_also") or {}).get("dir") or ""
    if two and not any(two) and str(also).rstrip("/").endswith("_one_sided"):
        k = also_reference(s)
        if k is not None:
            return k, "one-sided"
    return s, "both ways"
