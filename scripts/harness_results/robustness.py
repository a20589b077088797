"""Every claim's verdict judged again under every combination of the rule's free choices (rules.py,
"robustness"): the rho limits halved and doubled, the marginal band counted stable, the relative tie
of the noise 10 %, 5 % or none, the reference's floor, its Richardson estimate or twice the floor,
a run that tunnels up to 10 nodes over the window still evidence (the rule: none), two decisive
comparisons sufficing (the rule: three), and a run helping at 80 % of the no-force run's figures
(the rule: 90 %), rho's input power over the whole time before the window (the old normalisation,
with the limits as they were calibrated for it: rules.renormalised_rho converts a row that records
its steps and rho_norm; the report's runs from their summaries), the noise's floor with the scene's
mesh floor (the sphere's reference on a refined mesh against its own), the final window halved and
doubled and every method judged against the two-sided reference instead of the reference of its kind
(rules.variant_rows: accuracy_time.csv's runs judged again, accuracy_variants.csv): VARIANTS,
3 x 2 x 2 x 2 x 2 x 2 x 3 x 2 x 3 x 4 = 6912, the first the rule as written, and one more: the
within-noise comparisons counted on neither side, the rest as written (6913).

A verdict is stated as it is only when every variant gives it; otherwise it is "fragile", with the
verdicts it flips to and the choices under which it does (stated_verdict). The choices the committed
study files cannot vary are said (NOT_VARIED): the window's length outside accuracy_time.csv, the
reference's kind outside the files whose rows name it and record the two-sided error beside; a stable row of a file without a contact_power_ratio column keeps an unknown rho, so it
stays stable under every limit (rules.reclassify_row).

results/robustness.csv: one row per claim's verdict and variant (the variant's choices, its verdict,
its counts and its share for: the comparisons for the claim over its decisive ones). The
specification curve (figures/robustness.pdf and .png): per verdict, the share for over the variants,
sorted, coloured by the variant's verdict.
"""

import os
import textwrap

from . import rules, writers

VARIANTS = [rules.Variant(rho, marginal, tie, floor, tunnel, minimum, helps, norm, window, reference)
            for window in (1.0, 0.5, 2.0) for reference in (rules.OF_ITS_KIND, "both ways")
            for norm in ("recorded", "before") for minimum in (3, 2) for helps in (0.9, 0.8) for tunnel in (0, 10)
            for rho in (1.0, 0.5, 2.0)
            for marginal in ("unstable", "stable") for tie in (0.10, 0.05, 0.0)
            for floor in ("floor", "richardson", "double", "mesh")]
# and one choice made alone, the rest as written: the within-noise comparisons counted on neither side
# (rules.Variant.noise_reading; a product over it too would double the table)
VARIANTS.append(rules.Variant(noise_reading=rules.NEITHER))
# The choices a variant makes, by attribute, as robustness_text and moved_by say them.
DIMENSIONS = (("rho_scale", "the rho limits"), ("marginal", "the marginal band"), ("tie", "the relative tie"),
              ("floor", "the noise's floor"), ("tunnel_limit", "the tunnelled nodes allowed"),
              ("min_decisive", "the decisive comparisons needed"), ("helps", "the helping share"),
              ("rho_norm", "rho's normalisation"), ("window", "the window's length"),
              ("reference", "the reference's kind"), ("noise_reading", "how within-noise comparisons count"))
NOT_VARIED = ("the window's length (halved, doubled) outside accuracy_time.csv and the report's runs: it varies the rows "
              "of accuracy_time.csv (accuracy_variants.csv, the study's runs judged again from their steps.csv) and "
              "the report's runs ((b): rewindow.py on their steps.csv) only, and "
              "the other files' rows stand as they are under it; the reference's kind (every method against the "
              "two-sided reference) outside accuracy_time.csv, ablation.csv, convergence.csv (no claim reads it), orient.csv and regime.csv (files whose rows name "
              "their reference and record the two-sided error beside it: under that choice their rows take "
              "the two-sided largest position error, their other window figures stay those against the reference of "
              "their kind; regime.csv's swapped rows, swap.csv, region.csv and restriction.csv are measured against the "
              "two-sided reference as written); the share of 20 % that separates mixed from the two "
              "verdicts; each claim's "
              "own thresholds ((b)'s 5 %, 100 steps and 5 %, the factor 2 of (d)'s collision unit, real time's budget of one step (the scene's dt) and 1.5x; (c), (d) as stated and (e) vary their own thresholds in their sections). "
              "region.csv has no rho column (its unstable and marginal rows give it in "
              "their reasons) and does not record rho's normalisation: its stable rows stay stable under every rho limit "
              "and its rho as recorded under the old normalisation; realtime.csv records neither rho "
              "nor reasons: its classes stand under every variant; rho over the time before the window (the old "
              "normalisation, with the limits as they were calibrated for it: the same as limits 5 to 14 times "
              "tighter on these scenes' runs) converts the rows that record their steps and rho_norm and the "
              "report's runs from their summaries; the mesh floor is measured on the sphere only (its reference on a "
              "mesh refined once, references_differences.csv): the cylinder's and the implant's comparisons keep "
              "their reference's floor under it")
COLUMNS = ["claim", "variant", "rho_scale", "marginal", "tie", "floor", "tunnel_limit", "min_decisive", "helps",
           "rho_norm", "window", "reference", "noise_reading", "verdict", "for", "against", "noise", "not_judged",
           "share_for"]


def verdicts_of(records):
    """{prefix: (verdict, {"for", "against", "noise", "not judged"})} from the claims' macros (a claim's
    verdict macro <prefix>Verdict and its counts)."""
    out = {}
    for r in records:
        m = dict(r.macros)
        for name, value in r.macros:
            if name.endswith("Verdict"):
                p = name[:-len("Verdict")]
                counts = {k: int(m[p + key]) if str(m.get(p + key, "")).isdigit() else 0
                          for k, key in (("for", "For"), ("against", "Against"), ("noise", "Noise"),
                                         ("not judged", "NotJudged"))}
                out[p] = (value, counts)
    return out


def judge_variants(root, judge_all, make_context, variants=VARIANTS):
    """[(variant, verdicts_of(records))] with the claims judged under each variant."""
    out = []
    for v in variants:
        with rules.using(v):
            out.append((v, verdicts_of(judge_all(make_context(root)))))
    return out


def share_for(t):
    """The comparisons for over the decisive ones (None without any decisive)."""
    d = t["for"] + t["against"] + t["noise"]
    return t["for"] / d if d else None


def summary(results, only=None):
    """{prefix: {"verdict": as written, "agree": n, "total": n, "flips": [(variant, verdict)], ...}} (the
    prefixes in `only` alone where given)."""
    base = results[0][1]
    out = {}
    for p, (verdict, _t) in base.items():
        if only is not None and p not in only:
            continue
        flips = [(v, got[p][0]) for v, got in results[1:] if p in got and got[p][0] != verdict]
        distinct = {tuple(sorted(got[p][1].items())) for _v, got in results if p in got}
        out[p] = {"verdict": verdict, "total": len(results), "agree": len(results) - len(flips), "flips": flips,
                  "distinct": len(distinct), "moved_by": moved_by(results, p)}
    return out


def moved_by(results, p):
    """The dimensions (DIMENSIONS' words) whose choice changes verdict p's counts with every other
    choice held: those that act on it; the others leave it where it is, however many variants they
    make."""
    out = []
    for attr, say in DIMENSIONS:
        groups = {}
        for v, got in results:
            if p not in got:
                continue
            key = tuple(getattr(v, a) for a, _s in DIMENSIONS if a != attr)
            groups.setdefault(key, set()).add(tuple(sorted(got[p][1].items())))
        if any(len(g) > 1 for g in groups.values()):
            out.append(say)
    return out


def _choices_behind(flips):
    """The choices every flipping variant shares and the rule as written does not make (text: "rho
    limits x2 and marginal counted stable, together" where they share several), or None when they
    share none."""
    d = rules.DEFAULT
    parts = []
    for attr, say in (("rho_scale", lambda x: "rho limits x%g" % x), ("marginal", lambda x: "marginal counted %s" % x),
                      ("tie", lambda x: "tie %g %%" % (100 * x)), ("floor", lambda x: "floor %s" % x),
                      ("tunnel_limit", lambda x: "up to %d tunnelled nodes" % x),
                      ("min_decisive", lambda x: "%d decisive comparisons suffice" % x),
                      ("helps", lambda x: "helps at %g %%" % (100 * x)),
                      ("rho_norm", lambda x: {"loading": "rho over the loading period",
                                              "before": "rho over the time before the window"}.get(x, "rho as recorded")),
                      ("window", lambda x: "window x%g" % x),
                      ("reference", lambda x: "reference %s" % x),
                      ("noise_reading", lambda x: "within-noise comparisons %s" % (
                          "on neither side" if x == rules.NEITHER else "as not for"))):
        vals = {getattr(v, attr) for v, _ in flips}
        if getattr(d, attr) not in vals:
            parts.append(" or ".join(say(x) for x in sorted(vals, key=str)))
    if len(parts) > 1:  # every flipping variant makes all of them: they flip it together
        return " and ".join(parts) + ", together"
    return parts[0] if parts else None


def robustness_text(s):
    """"robust: 54 of 54 variants" or "fragile: 36 of 54 variants agree; flips to inconclusive (18:
    rho limits x0.5)"."""
    moved = ("no variant moves its counts" if s.get("distinct", 1) == 1 else
             "%d different counts over the variants; moved by %s of the %d choices: %s" % (
                 s["distinct"], len(s.get("moved_by", [])), len(DIMENSIONS), ", ".join(s.get("moved_by", []))))
    if not s["flips"]:
        return "robust: %d of %d variants (%s)" % (s["agree"], s["total"], moved)
    by = {}
    for v, verdict in s["flips"]:
        by.setdefault(verdict, []).append((v, verdict))
    parts = []
    for verdict, fl in sorted(by.items()):
        behind = _choices_behind(fl)
        # the variants that change one choice alone and flip it (said unless that choice is `behind`)
        alone = sorted({v.name() for v, _ in fl if v.name().count(",") == 0} - {behind})
        parts.append("to %s in %d (%s%s)" % (verdict, len(fl), behind or "e.g. " + fl[0][0].name(),
                                             "; alone: " + ", ".join(alone) if alone else ""))
    return "fragile: %d of %d variants agree (%s); flips %s" % (s["agree"], s["total"], moved, ", ".join(parts))


def stated_verdict(s):
    """The verdict as claims.md and the report state it: as written when every variant agrees, else
    "fragile (<as written> as written)"."""
    if not s["flips"] or s["verdict"] in (rules.NOT_TESTED,):
        return s["verdict"]
    return "fragile (%s as written)" % s["verdict"]


def write_csv(root, results, name="robustness.csv"):
    """results/robustness.csv (or `name` in root)."""
    rows = []
    for v, got in results:
        for p, (verdict, t) in sorted(got.items()):
            sf = share_for(t)
            rows.append(dict(zip(COLUMNS, [p, v.name(), "%g" % v.rho_scale, v.marginal, "%g" % v.tie, v.floor,
                                           v.tunnel_limit, v.min_decisive, "%g" % v.helps, v.rho_norm,
                                           "%g" % v.window, v.reference, v.noise_reading, verdict,
                                           t["for"], t["against"], t["noise"], t["not judged"],
                                           "" if sf is None else "%.4g" % sf])))
    path = os.path.join(root, name)
    writers.write_csv(path, rows, COLUMNS)
    return path


COLOURS = {rules.SUPPORTED: "#1b7837", rules.NOT_SUPPORTED: "#b2182b", rules.MIXED: "#e08214",
           rules.INCONCLUSIVE: "0.6", rules.NOT_TESTED: "0.85"}


def plot(root, results, labels):
    """figures/robustness.{pdf,png}: per verdict (labels: {prefix: title}), the share for over the
    variants, sorted (a variant without decisive comparisons at 0, hollow), coloured by verdict, the
    verdict rule's bounds dashed."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    prefixes = [p for p in labels if p in results[0][1]]
    rows = (len(prefixes) + 1) // 2  # two columns of panels: the figure fits a page with its caption
    fig, axes = plt.subplots(rows, 2, figsize=(7.0, 1.1 * rows + 0.7), sharex=True, squeeze=False)
    for ax in axes.flat[len(prefixes):]:
        ax.set_visible(False)
    for ax, p in zip(axes.flat, prefixes):
        pts = []
        for v, got in results:
            verdict, t = got[p]
            sf = share_for(t)
            pts.append((-1.0 if sf is None else sf, verdict, sf is None))
        pts.sort(key=lambda x: x[0])
        # one scatter per panel, its markers rasterised (thousands of variants: a vector marker each would
        # make the PDF megabytes); the axes, text and bounds stay vector
        cols = [COLOURS.get(verdict, "k") for _y, verdict, _n in pts]
        ax.scatter(range(len(pts)), [max(y, 0.0) for y, _v, _n in pts], s=6, linewidths=0.6, edgecolors=cols,
                   facecolors=["none" if none else c for (_y, _v, none), c in zip(pts, cols)], rasterized=True)
        for b in (rules.MIXED_SHARE, 1.0 - rules.MIXED_SHARE):
            ax.axhline(b, color="0.5", lw=0.6, ls="--")
        ax.set_ylim(-0.08, 1.08)
        ax.set_yticks([0, 0.5, 1])
        ax.set_ylabel("share for", fontsize=6)
        ax.set_title(textwrap.fill(labels[p], 60), fontsize=6, loc="left")
        ax.tick_params(labelsize=6)
    for ax in axes[-1, :]:
        ax.set_xlabel("variant of the rule (sorted by share for)", fontsize=6)
    handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=k, ms=4) for k, c in COLOURS.items()]
    handles.append(plt.Line2D([], [], marker="o", ls="", mfc="none", mec="k", label="no decisive comparison", ms=4))
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    d = os.path.join(root, "figures")
    os.makedirs(d, exist_ok=True)
    for ext in ("pdf", "png"):
        fig.savefig(os.path.join(d, "robustness." + ext), dpi=130,
                    metadata={"CreationDate": None} if ext == "pdf" else None)
    plt.close(fig)
    return os.path.join(d, "robustness.pdf")


def results_from_csv(root, name="robustness.csv"):
    """[(variant name, {prefix: (verdict, counts)})] read back from robustness.csv, in its order: what
    plot draws, without judging the variants again."""
    import csv
    out, index = [], {}
    with open(os.path.join(root, name)) as f:
        for r in csv.DictReader(f):
            if r["variant"] not in index:
                index[r["variant"]] = len(out)
                out.append((r["variant"], {}))
            out[index[r["variant"]]][1][r["claim"]] = (r["verdict"], {
                "for": int(r["for"]), "against": int(r["against"]), "noise": int(r["noise"]),
                "not judged": int(r["not_judged"])})
    return out
