#!/usr/bin/env python3
"""Tests the claims of the paper on the results and writes the numbers and a verdict per claim:
results/claims.md, and for the report results/tables/claims_b.tex, results/tables/claims_verdicts.tex
and results/tables/claims_macros.tex.

Usage: claims.py [RESULTS_DIR]   (default: results)

One module per claim under scripts/harness_results/claims/ states its test and its verdict rule:
(a) the plane beats the line in implant expansion (the equal-footing grid, each at its best, and
oriented the same way), (b) penetrating points are few and eliminated within several iterations
(the runs' episodes, guest and host nodes apart), (c) restrictions cost much time (the bound's
cost included), (d) voxelization is one of the fastest searches at matched error, (e) a large
region detects collisions under any deformation (a skin wrapped around a limb), which body carries
the grid (a finding), real time (collision unit and simulator), and the completed model. The
comparison and verdict rules (supported, not supported, mixed, inconclusive, not tested)
are in harness_results/rules.py; claims.md and the LaTeX files are written by
harness_results/claims/report.py.
"""

import sys

from harness_results import runs
from harness_results.claims import report
from harness_results.claims.common import Context


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    ctx = Context(root)
    if not ctx.runs:
        sys.exit("claims: no runs under %s" % runs.runs_dir(root))
    report.write_all(root, ctx)


if __name__ == "__main__":
    main()
