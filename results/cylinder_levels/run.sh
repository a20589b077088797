#!/bin/bash
# Levels 2 and 3 of the cylinder's two-sided reference (harness reference's level scene: CGAL, the line,
# both ways, k_c = 500 * 2^L, dt / 2^L, the guard substepping) settled at the scene's tolerance (1e-5: l2_5,
# l3_5) and at 1e-6 (l2_6, l3_6), into this folder (about 15 min on 2 cores; surfaces.csv and run.json kept).
# Then: scripts/cylinder_levels.py results
H=${HARNESS:-build/bin/harness}
D=$(dirname "$0")
lvl() {  # level tolerance folder
  local L=$1 tol=$2 out=$D/$3 div=$((1<<$1)) k=$((500<<$1))
  HARNESS_THREADS=1 $H run cylinder_press --out $out --quiet --dt-divide $div \
    --set output.frames_every=0 --set references.solvers='[]' --set time.guard='"substep"' \
    --set "contacts.0.force={\"stiffness\":$k}" --set "time.settle={\"tolerance\":$tol,\"max_steps\":40000}"
}
( lvl 2 1e-5 l2_5; lvl 3 1e-5 l3_5 ) &
( lvl 2 1e-6 l2_6; lvl 3 1e-6 l3_6 ) &
wait
# Committed form (results/README.md): steps.csv.gz, level and run surfaces gzipped.
${PYTHON:-/usr/bin/python3} scripts/store_results.py results/cylinder_levels
