#!/usr/bin/env python3
"""Figures of the reproduction, from results/runs/* (see results/README.md).

Usage: figures.py [RESULTS_DIR]     (default: results; writes RESULTS_DIR/figures/<name>.{pdf,png})

  snapshots_<scene>   both surfaces in 3D at four instants, line (top) and plane (bottom):
                      truly penetrating vertices marked (POINT_DATA of the frames), the voxel
                      region of that step drawn as a box (region_* columns of steps.csv)
  section_<scene>     cross-section (triangles cut by a plane: sphere z = 0, cylinder x = 0,
                      implant y = 0 showing the tissue dome lifted by the implant), the rest
                      state in grey
  timeseries_<scene>  true penetrations (guest, host), detected contacts, maximum residual
                      depth and contact force per step, line against plane
  episodes            how many steps a node stays truly penetrating, line against plane
Each figure is drawn at the size paper/main.tex prints it (style.TEXT: the text width;
style.HALF: half of it, the time series), with 8 pt text (7 pt at the least), and written
as a vector PDF (what the report includes; the 3D surfaces inside it rasterised at 300 dpi) and
a 300 dpi PNG. Deterministic: fixed run order, no dates, fixed sizes and resolution.
The figures are drawn by scripts/harness_results/figures.py.
"""

import sys

from harness_results import needs

needs.numpy_and_matplotlib('figures.py')

from harness_results import figures, runs  # noqa: E402


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    if not figures.draw_all(root):
        sys.exit("figures: no runs under %s" % runs.runs_dir(root))


if __name__ == "__main__":
    main()
