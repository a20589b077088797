#!/bin/bash
# The cylinder on a layer that resists inversion (experiments/scenes/claims/cylinder_press_bulk.json:
# effect "bulk", bulk modulus 1e4 Pa, alternating diagonals, a cylinder of 48 segments), studied as
# the bundled cylinder is, into results/cylinder_bulk/study/:
#   accuracy_time.csv, accuracy_variants.csv, figures/, tables/   scripts/study.py accuracy on the scene,
#       at the bundled cylinder's voxels (8 and 16 mm: --voxel 0.008), against its references
#   runs/cylinder_press{,_f0003}_{line,plane}/   the report's four cylinder runs (scripts/reproduce.sh's
#       command line, the scene's two-sided reference, no frames)
# Its references are this folder's references/cylinder_press_bulk{,_one_sided}: links to
# ../alternating48_{two,one} (results/cylinder_bulk/run.sh; the same scene, made with the same
# arithmetic: levels 0 and 1 made again from this scene file give the same state hashes).
# About 60 min on 2 cores. Then scripts/claims.py results judges the verdicts that read the cylinder
# again with these rows in place of the bundled cylinder's (claims/layer.py; claims.md's last section).
set -euo pipefail
cd "$(dirname "$0")/../.."
H=${HARNESS:-build/bin/harness}
PY=${PYTHON:-/usr/bin/python3}
S=experiments/scenes/claims/cylinder_press_bulk.json
D=results/cylinder_bulk/study
$PY scripts/study.py accuracy --harness "$H" --scene $S --out $D --reference $D/references/cylinder_press_bulk --voxel 0.008
run() {  # folder eliminator force
  rm -rf "${D:?}/runs/$1"
  HARNESS_THREADS=1 "$H" run $S --out "$D/runs/$1" --quiet --compare $D/references/cylinder_press_bulk \
    --set 'contacts.0.detector="voxel"' --set "contacts.0.eliminator=\"$2\"" --set "contacts.0.force=$3" \
    --set contacts.0.two_sided=false --set 'references.solvers=["cgal"]' --set references.every=10 \
    --set output.frames_every=0
}
( run cylinder_press_line line '"auto"'; run cylinder_press_f0003_line line 0.003 ) & p1=$!
( run cylinder_press_plane plane '"auto"'; run cylinder_press_f0003_plane plane 0.003 ) & p2=$!
wait $p1; wait $p2
# Committed form (results/README.md): steps.csv.gz, level and run surfaces gzipped.
${PYTHON:-/usr/bin/python3} scripts/store_results.py results/cylinder_bulk
