#!/usr/bin/env python3
"""Tables of the reproduction, from results/runs/* (steps.csv, summary.json, frames).

Usage: tables.py [RESULTS_DIR]    (default: results; writes RESULTS_DIR/tables/)

  accuracy.{md,tex,csv}     per scenario and eliminator: truly penetrating nodes (guest + host)
                            at the end and at the peak (steps.csv, CGAL), maximum residual depth
                            at the end and at the peak (mm and voxels = depth / voxel_size_used),
                            recall, precision
  deformation.{md,tex,csv}  per body: largest displacement max_i |x_i(end) - x_i(0)| over the
                            surface vertices (first and last frames), and largest deformation
                            max_i |d_i - mean(d)| (d_i the displacement: the rigid translation
                            removed)
  timing.{md,tex,csv}       medians of the per-step wall times (summary.json timing_us), us
  scenes_bodies.{md,tex,csv}, scenes_contacts.{md,tex,csv}
                            the scenarios' parameters, from the resolved scenes of the runs
The first two are identical from one run to the next; timing is measured and varies.
The tables are made by scripts/harness_results/tables.py.
"""

import sys

from harness_results import runs, tables


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    if not tables.write_all(root):
        sys.exit("tables: no runs under %s" % runs.runs_dir(root))


if __name__ == "__main__":
    main()
