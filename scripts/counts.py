#!/usr/bin/env python3
"""The counts the report quotes, as LaTeX macros taken from the results (never typed): which ones,
and from which files, is said in scripts/harness_results/counts.py.

Usage: counts.py [RESULTS_DIR]     (default: results; writes RESULTS_DIR/tables/counts.tex)
"""

import argparse
import os
import sys

from harness_results import counts


def main():
    ap = argparse.ArgumentParser(description="Write RESULTS_DIR/tables/counts.tex, the report's counts.")
    ap.add_argument("root", nargs="?", default="results", metavar="RESULTS_DIR",
                    help="the results folder (default: results)")
    a = ap.parse_args()
    if not os.path.isdir(a.root):
        print("counts.py: %s: not a folder" % a.root, file=sys.stderr)
        sys.exit(2)
    counts.write(a.root)


if __name__ == "__main__":
    main()
