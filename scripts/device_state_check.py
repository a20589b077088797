#!/usr/bin/env python3
"""The GPU's final states against the CPU's: results/device/state_check.csv.

Usage: device_state_check.py [RESULTS_DIR] [HARNESS]   (defaults: results, build/bin/harness)

Rows: every device run of RESULTS_DIR/device/runs/ with a `cpu_check` in its summary.json (made
on the GPU machine by `harness run --device cuda --check-cpu`), as recorded; and every full run
(`*_voxel_exact_full`, whose summary has no cpu_check: made before device_check.sh passed
--check-cpu to them) checked here: the CPU's `harness run SCENE --steps N --set
contacts.0.detector='"voxel_exact"' --set references.solvers='[]'` gives its state hash; where the
hashes differ, `harness run ... --device cpu` (the device's kernel bodies on the CPU, bit-identical
to the CPU's step: ctest gpu_kernels_*) gives its state.csv, and the largest node distance to the
GPU's state.csv.gz is computed. Runs the CPU for a few minutes; run with /usr/bin/python3 or
$PYTHON. The check: scripts/harness_results/state_check.py.
"""

import os
import sys

from harness_results import state_check


def main(argv):
    results = argv[1] if len(argv) > 1 else "results"
    harness = argv[2] if len(argv) > 2 else os.path.join("build", "bin", "harness")
    state_check.write(results, harness)


if __name__ == "__main__":
    main(sys.argv)
