#!/usr/bin/env python3
"""Tests the paper's claims on the committed results and states what the data say:
results/SUMMARY.md (the answer first: one line per claim, what the paper's model does well and where
it fails, what accuracy costs per method), results/claims.md (each claim's declared comparisons,
its effects with their intervals, where it holds and where it fails), results/specifications.csv
(each claim under every distinct specification of the remaining choices), and for the report
results/tables/claims_verdicts.tex and results/tables/claims_macros.tex.

Usage: claims.py [RESULTS_DIR]   (default: results)

The judge is scripts/harness_results/judge/: choices.py (every analysis choice, one table),
measure.py (a run: failed, stability, error and time with intervals), claims.py (each claim's
declared comparisons and its verdict from the intervals), state.py (the files above).
"""

import os
import sys

from harness_results.judge import state


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    if not os.path.exists(os.path.join(root, "accuracy_time.csv")):
        print("claims.py: %s: no accuracy_time.csv (run scripts/study.py accuracy first)" % root, file=sys.stderr)
        sys.exit(2)
    for res, _revs in state.write_all(root):
        print("claims: (%s) %s: %s" % (res.key, res.title, res.verdict))


if __name__ == "__main__":
    main()
