#!/usr/bin/env python3
"""Deletes the frames of results/runs/* that no figure or table uses: keeps, for every body,
the snapshot instants of figures.py (which include step 0 and the last step, the ones
tables.py uses for displacements): harness_results/runs.py, prune_frames.
Usage: prune_frames.py [RESULTS_DIR]"""

import sys

from harness_results import runs


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    kept, removed = runs.prune_frames(root)
    print("prune_frames: kept %d frames, removed %d" % (kept, removed))


if __name__ == "__main__":
    main()
