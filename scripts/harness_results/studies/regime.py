"""study.py regime: the paper's model at its best before it is judged (issue: claims (a), (b) and the
host/guest swap have almost no decisive comparison at the scenes' settings, because the paper's runs
either do nothing or are not stable). The paper says its force "was defined experimentally for every
task": this study gives it that search.

On the implant (the scene of claim (a)) and the spheres (REGIME_SCENES; a user's scene with --scene),
the paper's voxel model with the line and the plane, the scene's constant forces (SCENE_FORCES) and
`auto`, the footing voxels (the pair's and twice it), each in every REGIME: the scene as written; dt / 8 (`--dt-divide 8`: every
key that counts steps scaled, so the same physical time); the grid over the host's full box; and,
named as a variant and not the paper's method, a damping term on the contact force
(contacts.N.damping, N s/m per contact: F -> max(0, F - c v_n)) at two strengths. Every run once,
untimed (-j at once), over the final window against the reference of the model's kind (one-sided
where the scene has one: the limit the voxel model converges to; the two-sided error beside it); the
scene with no contact force beside (the run a useful setting must beat). Where a run is evidence (stable, helps, tunnels
nothing), the same setting is run again with host and guest swapped (the grid on the other body),
against the two-sided reference only (the one-sided reference is the limit of the scene's placement:
the swap is judged on the two-sided errors of both placements, as study.py swap does).
Per run its guest's penetration episodes (claim (b)'s criteria: claims/b_episodes.py) are kept.
-> regime.csv, tables/regime.md. The claims judge (a), (b) and the swap on it (claims/regime.py),
each verdict naming the regimes its comparisons come from.
"""

import os

from .. import rules, runner, writers
from .. import episodes as b_episodes
from .accuracy import FOOTING_VOXELS, NO_FORCE
from .common import (config_sets, figures, footing_voxels, force_label, pair_bodies, read_rows, reference_dir,
                     reference_of_kind, scenes, table_path, with_both_kinds)
from .common import columns_of
from .swap import SWAP_BODIES

# The constant forces searched, per scene (`auto` with each): the implant's from the accuracy study's
# footing forces; the sphere's one step lower (ablation.csv: on the sphere every constant force of
# 0.01 N or more is no better than no force at every voxel, and 0.0005 N is its only force that is
# stable and helps at a voxel of the ablation). A user's scene gets FORCES.
FORCES = ["0.001", "0.003", "0.01", "auto"]
SCENE_FORCES = {"implant_expansion": FORCES, "sphere_collision": ["0.0005", "0.001", "0.003", "auto"]}
ELIMINATORS = ["line", "plane"]
# (name, extra --set overrides or raw options): the regimes searched. Damping in N s/m per contact:
# with the implant's guest nodes of about 0.1 g at dt 1e-4 s, 0.01 and 0.1 take 1 % and 10 % of a
# node's relative speed per step (c dt / m; explicit damping is stable below 2); with the sphere's
# nodes of about 22 mg (0.0352 kg over 1610 nodes) at dt 5e-5 s, 2.3 % and 23 % (a node in several
# contacts takes each one's). In regime.csv three of the sphere's runs at 0.1 (the line at 8 mm) end
# with dt above the springs' limit (the guard's Gershgorin bound: the exponential law stiffened), two
# of them with the contact kicking the bodies: they are unstable, with why.
REGIMES = [("as written", []), ("dt/8", ["--dt-divide=8"]), ("region full", ['contacts.0.region="full"']),
           ("damping 0.01", ["contacts.0.damping=0.01"]), ("damping 0.1", ["contacts.0.damping=0.1"])]
# The implant (claim (a)'s scene) and the spheres (claim (b)'s and the swap's too). Not the cylinder:
# its references invert the layer's top cells under the cylinder (results/cylinder_levels.csv), so
# its errors would judge the search against a reference that is itself in question.
REGIME_SCENES = ["implant_expansion", "sphere_collision"]


def regime_scenes(a):
    """The bundled implant and spheres, or the user's scene."""
    return scenes(a) if getattr(a, "user", None) else REGIME_SCENES


def forces_of(scene):
    """The forces searched on `scene` (SCENE_FORCES; FORCES for a scene it does not name)."""
    return SCENE_FORCES.get(scene, FORCES)


def forces_text(scenes_, tex=False):
    """"0.001, 0.003, 0.01 N and auto (implant_expansion); ..." for `scenes_`: the forces each was
    searched with (LaTeX with `tex`)."""
    def one(scene):
        fs = [f for f in forces_of(scene) if f != "auto"]
        n = "~N" if tex else " N"
        auto = "\\code{auto}" if tex else "`auto`"
        return ", ".join(fs) + n + " and " + auto
    if not tex:
        return "; ".join("%s (%s)" % (one(sc), sc) for sc in scenes_)
    return "; ".join("%s (%s)" % (one(sc), "\\code{%s}" % sc.replace("_", "\\_")) for sc in scenes_)


def grid(a, scene):
    """(eliminator, force, voxel, regime name, regime sets) of the search on `scene`."""
    return [(e, f, v, name, sets) for name, sets in REGIMES for v in footing_voxels(a, scene, FOOTING_VOXELS)
            for e in ELIMINATORS for f in forces_of(scene)]


def folder(scene, elim, force, voxel, regime, swapped):
    return "regime/%s/%s_%s_%g_%s%s" % (scene, elim, force_label(force), 1e3 * voxel, regime.replace(" ", "_").replace("/", "-"),
                                        "_swapped" if swapped else "")


def sets_of(elim, force, voxel, regime_sets, host=None, guest=None):
    extra = list(regime_sets)
    if host is not None:
        extra += ['contacts.0.host="%s"' % host, 'contacts.0.guest="%s"' % guest]
    return config_sets("voxel", voxel, elim, force, extra)


def dt_divide(regime_sets):
    """The regime's dt divisor (1 unless it passes --dt-divide)."""
    return next((int(x.split("=", 1)[1]) for x in regime_sets if x.startswith("--dt-divide=")), 1)


def episodes(path, divide=1):
    """Claim (b)'s figures of a run's guest nodes (b_episodes.run_figures), {} where it has none. At
    dt / N (`divide`) the run's steps are N times shorter and its measured steps N times apart (every
    key that counts steps is scaled): the lengths are given in the scene's steps (the run's / N), the
    same physical time as (b)'s 100 steps at the scene's dt, and the criteria judged on them."""
    try:
        _s, g, _h = b_episodes.run_figures(path)
    except (OSError, KeyError, ValueError):
        return {}
    nan = float("nan")
    p90 = g["p90"] / divide if g["p90"] is not None else nan
    reasons = b_episodes.failing_criteria(g["peak_frac"], float(p90), g["open_frac"], unit="scene steps")
    return {"ep_episodes": g["episodes"], "ep_median": g["median"] / divide if g["median"] is not None else nan,
            "ep_p90": p90, "ep_failed_frac": g["open_frac"], "ep_through_frac": g["through_frac"],
            "ep_peak_frac": nan if g["peak_frac"] is None else g["peak_frac"], "ep_passages": "yes" if g["passages"] else "no",
            "ep_holds": "no" if reasons else "yes", "ep_why": "; ".join(reasons) if reasons else "all three met"}


def row(scene, elim, force, voxel, regime, swapped, host, guest, s, path, kind):
    divide = dt_divide(dict(REGIMES).get(regime, []))
    r = dict(figures(s), scene=scene, config="voxel %g mm" % (1e3 * voxel), eliminator=elim, force=force_label(force),
             voxel_mm=1e3 * voxel, regime=regime, swapped="yes" if swapped else "no", host=host, guest=guest,
             dt_divide=divide)
    r.update(episodes(path, divide))
    return with_both_kinds(r, s, kind)


def evidence_either_kind(r, base):
    """Whether the scene placement's row `r` is evidence (rules.evidence_gap) against the reference of
    its kind or against the two-sided one (its helps judged again on its two-sided error against
    `base`): the settings whose swap is run (the swap is judged on the two-sided errors)."""
    if rules.evidence_gap(r) is None:
        return True
    two = rules.two_sided_row(r, base)
    return two is not r and base is not None and rules.evidence_gap(two) is None


def run(a):
    rows, configs, kinds = [], [], {}
    for scene in regime_scenes(a):
        kinds[scene] = reference_of_kind(a, scene, False)
        host, guest = pair_bodies(a, scene, SWAP_BODIES)
        v0 = footing_voxels(a, scene, FOOTING_VOXELS)[0]
        configs.append(((scene, "line", "0", v0, NO_FORCE, False, host, guest), scene,
                        folder(scene, "line", "0", v0, "no_force", False), sets_of("line", "0", v0, [])))
        for e, f, v, name, extra in grid(a, scene):
            configs.append(((scene, e, f, v, name, False, host, guest), scene, folder(scene, e, f, v, name, False),
                            sets_of(e, f, v, extra)))
    done = runner.run_configs(a, configs, {scene: k[1:] for scene, k in kinds.items()})
    for (meta, s), c in zip(done, configs):
        rows.append(row(*meta, s, os.path.join(a.results, "sweeps", c[2]), kinds[meta[0]][0]))
    bases = {r["scene"]: r for r in rows if r["regime"] == NO_FORCE}
    rules.mark_useless(rows, bases)
    # The swap where the scene's placement is evidence: the same setting, the grid on the other body.
    swaps = []
    for r in rows:
        if r["regime"] == NO_FORCE or not evidence_either_kind(r, bases.get(r["scene"])):
            continue
        extra = dict(REGIMES)[r["regime"]]
        force = "auto" if r["force"] == "auto" else r["force"][2:]
        v = r["voxel_mm"] / 1e3
        swaps.append(((r["scene"], r["eliminator"], force, v, r["regime"], True, r["guest"], r["host"]), r["scene"],
                      folder(r["scene"], r["eliminator"], force, v, r["regime"], True),
                      sets_of(r["eliminator"], force, v, extra, r["guest"], r["host"])))
    both = {scene: (reference_dir(a, scene), None) for scene in kinds}
    for (meta, s), c in zip(runner.run_configs(a, swaps, both), swaps):
        rows.append(row(*meta, s, os.path.join(a.results, "sweeps", c[2]), "both ways"))
    write(a, rows)


COLUMNS = ["scene", "config", "eliminator", "force", "voxel_mm", "regime", "dt_divide", "swapped", "host", "guest", "stable",
           "stability", "why_unstable", "helps", "useless", "pos_err_max_mm", "pos_err_amp_mm", "gap_max_mm",
           "depth_max_mm", "tunnelled", "contact_power_ratio", "rho_norm", "recall", "precision", "steps", "ep_episodes",
           "ep_median", "ep_p90", "ep_failed_frac", "ep_through_frac", "ep_peak_frac", "ep_passages", "ep_holds",
           "ep_why", "reference", "pos_err_max_one_sided_mm", "pos_err_max_both_ways_mm"]


def write(a, rows):
    """regime.csv and tables/regime.md (helps and useless against the study's run without contact force)."""
    bases = {r["scene"]: r for r in rows if r["regime"] == NO_FORCE}
    rules.mark_useless(rows, bases)
    writers.write_csv(os.path.join(a.results, "regime.csv"), rows, columns_of(COLUMNS, rows))
    rows = read_rows(a, "regime.csv")  # the table from the file as written: --plots-only gives the same
    md = ["# The paper's model at its best: a search over regimes\n\n",
          "The paper's voxel model (line and plane; constant forces and `auto`: %s; the footing voxels) in each regime: "
          % forces_text(sorted({r["scene"] for r in rows})) +
          "the scene as written, dt / 8 (every step count scaled: the same physical time), the grid over the host's "
          "full box, and a damping term on the contact force (a variant, not the paper's method: F -> max(0, F - c "
          "v_n), c in N s/m per contact). Errors over the final window (mm) against the reference of the model's kind "
          "(`reference`: one-sided for the scene's placement, where the scene has one; the two-sided error beside it); "
          "evidence: stable, helps (beats the run without contact force) and tunnels nothing. Where the scene's "
          "placement is evidence against either reference, the same setting swapped (host and guest exchanged), "
          "against the two-sided reference only (the one-sided one is the limit of the scene's placement). Episodes (claim (b), guest nodes): count, 90th "
          "percentile length in the scene's steps (at dt / 8 the run's steps / 8: the same time), failed share (open at the end or through), peak share of nodes. Made by "
          "`scripts/study.py regime`.\n\n"]
    for scene in sorted({r["scene"] for r in rows}):
        sr = [r for r in rows if r["scene"] == scene]
        ev = [r for r in sr if r["regime"] != NO_FORCE and r["swapped"] == "no" and rules.evidence_gap(r) is None]
        md.append("## %s\n\n%d of %d settings are evidence; by regime: %s.\n\n" % (
            scene, len(ev), sum(1 for r in sr if r["regime"] != NO_FORCE and r["swapped"] == "no"),
            ", ".join("%s %d" % (name, sum(1 for r in ev if r["regime"] == name)) for name, _ in REGIMES)))
        md.append(writers.md_table(sr, ["regime", "eliminator", "force", "voxel_mm", "swapped", "stability", "useless",
                                        "pos_err_max_mm", "pos_err_amp_mm", "depth_max_mm", "tunnelled",
                                        "ep_episodes", "ep_p90", "ep_failed_frac", "ep_peak_frac", "why_unstable",
                                        "reference", "pos_err_max_both_ways_mm"],
                                   ["regime", "elim.", "force", "voxel (mm)", "swapped", "stability", "useless",
                                    "pos. error max (mm)", "error swing (mm)", "depth max (mm)", "tunnelled",
                                    "episodes", "p90 (scene steps)", "failed", "peak share", "why unstable",
                                    "reference", "pos. error both ways (mm)"]))
        md.append("\n")
    with open(table_path(a, "regime.md"), "w") as f:
        f.write("".join(md))


def plots(a):
    """tables/regime.md again from regime.csv (nothing is run)."""
    path = os.path.join(a.results, "regime.csv")
    if os.path.exists(path):
        write(a, read_rows(a, "regime.csv"))
