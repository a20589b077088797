"""The paper's claims, one module each. A module has `judge(ctx)` (ctx: common.Context, the results)
returning its common.Verdict: the verdict, its section of claims.md, its LaTeX macros and tables.
scripts/claims.py writes them in ORDER.

To add a claim: a module here whose judge() builds its comparisons with rules.decide (beyond the
noise; "not stable" when a run it rests on is not) and its verdict with rules.claim_verdict; its name in
ORDER (where its section goes in claims.md); its macros follow the others in claims_macros.tex.
"""

import importlib

# The order of the sections of claims.md.
ORDER = ["a_plane", "b_episodes", "c_restrictions", "d_voxel_speed", "e_region", "swap", "regime", "realtime", "completed"]


def module(name):
    """The module of claim `name`."""
    return importlib.import_module("." + name, __name__)


def judge_all(ctx, order=ORDER):
    """Every claim's Verdict, in `order`."""
    return [module(name).judge(ctx) for name in order]
