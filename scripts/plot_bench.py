#!/usr/bin/env python3
"""Scaling figure and ratio table of `harness bench` (its columns: docs/usage.md, "Performance").

Usage: plot_bench.py [BENCH_CSV] [RESULTS_DIR]
       (defaults: results/bench.csv, results; run with /usr/bin/python3 or $PYTHON)

  RESULTS_DIR/figures/bench_scaling.{pdf,png}
                                         time per step against nodes per body, log-log: every
                                         method with one thread (solid) and two (dashed); the two
                                         memory-bandwidth limits (stream_*) in grey; printed at
                                         the report's text width (harness_results/style.py: TEXT)
  RESULTS_DIR/tables/bench.md            the ratios the performance targets are stated in, each
                                         with its target and whether it holds, then every time;
                                         the GPU rows (device other than cpu: harness bench
                                         --device cuda) in a section of their own
  RESULTS_DIR/tables/bench_gpu.tex       the GPU rows: step and copy per size, their ratio, ns per
                                         spring, beside the CPU's one-thread step
A ratio whose rows are missing (e.g. a --quick bench has no 10^6 point) is reported as n/a.
Deterministic: fixed method order, no dates. Drawn and written by scripts/harness_results/bench.py.
"""

import os
import sys

from harness_results import needs

needs.numpy_and_matplotlib('plot_bench.py')

from harness_results import bench  # noqa: E402


def main(argv):
    csv_path = argv[1] if len(argv) > 1 else os.path.join("results", "bench.csv")
    out_dir = argv[2] if len(argv) > 2 else os.path.dirname(csv_path) or "results"
    if not bench.write_all(csv_path, out_dir):
        sys.exit("plot_bench: %s has no rows" % csv_path)


if __name__ == "__main__":
    main(sys.argv)
