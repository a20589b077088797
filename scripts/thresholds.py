#!/usr/bin/env python3
"""Measure the bundled scenarios and write results/thresholds.json: the CI accuracy thresholds.

Two methods per scenario, each run as the test runs it (settle at most SETTLE more steps, CGAL every
EVERY steps) and compared with the scenario's committed reference (results/references/<scene>/):
  the paper's voxel model  with the default the ablation chose (results/defaults.json); a scenario
                           without one gets no threshold for it, and the file says why;
  the completed model      voxel_exact, both ways, the penalty (k = 500 N/m): COMPLETED.
The figures are the run's final window (rules: scripts/harness_results/rules.py): position error and
gap as window means, depth and tunnelled nodes as window maxima, recall over the run. Each threshold
is the measured value times a stated margin (at most 1.5), with a floor for the lengths (the scale
below which the reference itself is not trusted) and for tunnelled nodes (1: one node may tunnel
at the measured value 0):
  max_pos_err_max  window mean of the largest distance of a surface vertex from the reference  x 1.5
  max_gap_max      window mean of the largest gap where the reference has contact             x 1.5
  max_depth_max    window maximum of the deepest penetration                                   x 1.5
  max_tunnelled    window maximum of the nodes that passed through the other body             x 1.5, at least 1
  min_recall       detected / truly penetrating guest nodes (1 when none)                      / 1.1
SETTLE, EVERY, MARGIN, FLOOR, COMPLETED and the measuring: scripts/harness_results/thresholds.py.
Run deliberately, after a change that is meant to move accuracy (it is NOT part of reproduce.sh:
thresholds must not follow the code automatically).
Usage: scripts/thresholds.py [--harness build/bin/harness] [--results results]
"""
import argparse

from harness_results import thresholds


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--harness", default="build/bin/harness")
    ap.add_argument("--results", default="results")
    thresholds.write(ap.parse_args())


if __name__ == "__main__":
    main()
