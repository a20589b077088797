#!/usr/bin/env python3
"""The counts the report quotes, as LaTeX macros taken from the results (never typed): which ones,
and from which files, is said in scripts/harness_results/counts.py.

Usage: counts.py [RESULTS_DIR]     (default: results; writes RESULTS_DIR/tables/counts.tex)
"""

import sys

from harness_results import counts


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    counts.write(root)


if __name__ == "__main__":
    main()
