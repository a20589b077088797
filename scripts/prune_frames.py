#!/usr/bin/env python3
"""Deletes the frames of results/runs/* that no figure or table uses: keeps, for every body,
the snapshot instants of figures.py (which include step 0 and the last step, the ones
tables.py uses for displacements). Usage: prune_frames.py [RESULTS_DIR]"""

import os
import sys

from harness_results import reader, runs


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    removed = kept = 0
    for _key, _scene, _title, _force, _elim, path in runs.existing_runs(root):
        keep = set(runs.snapshot_steps(reader.load_summary(path)))
        for body, steps in sorted(runs.frames_available(path).items()):
            for s in steps:
                if s in keep:
                    kept += 1
                else:
                    os.remove(runs.frame_path(path, body, s))
                    removed += 1
    print("prune_frames: kept %d frames, removed %d" % (kept, removed))


if __name__ == "__main__":
    main()
