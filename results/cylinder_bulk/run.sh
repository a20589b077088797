#!/bin/bash
# The cylinder's references with a layer that resists inversion: effect "bulk" with the layer's
# bulk_modulus 1e4 Pa (Poisson ratio 0.45 with the lattice's E = 3250 Pa, docs/scenes.md), and
#   aligned_*        the layer's surface split as the scene splits it (all quads along one diagonal)
#   alternating_*    split along alternating diagonals (shape.diagonals "alternating")
#   alternating48_*  alternating, and the cylinder with 48 segments instead of 24 (at least 5 levels)
# each reference both ways (*_two) and one way (*_one), into this folder: the reference's summary.json
# and settled surfaces, and each level's (levels/L); then the lattice's inverted rows at level 0 of
# each variant (scripts/lattice_inversion.py: inversion.csv, the 48 segments' inversion48.csv).
# About 110 min on 2 cores.
# Then: scripts/cylinder_bulk.py results
# The committed folders were made from the working tree of commit 1aa4d40 with this change (their
# summary.json's git_commit says 1aa4d40-dirty), before the effect was renamed from "volume" to
# "bulk" (their resolved scenes list "volume") and, for aligned_*, before the key shape.diagonals
# existed (their resolved scenes lack it; "aligned" is the split the generator made then). The
# arithmetic is the same, and so is the effect's place in a step.
H=${HARNESS:-build/bin/harness}
PY=${PYTHON:-/usr/bin/python3}
D=$(dirname "$0")
EFF='["springs","bulk","damping","gravity","pins","drivers","contact"]'
ref() {  # diagonals segments kind folder [options]
  local T; T=$(mktemp -d)
  local opts=("${@:5}"); [[ $3 == one ]] && opts+=(--one-sided)
  HARNESS_THREADS=1 $H reference cylinder_press --quiet "${opts[@]}" --out "$T" --set "effects=$EFF" \
    --set bodies.0.material.bulk_modulus=10000 --set "bodies.0.shape.diagonals=\"$1\"" \
    --set "bodies.1.shape.segments=$2" || return 1
  rm -rf "${D:?}/$4"; mkdir -p "$D/$4"
  cp "$T/summary.json" "$T/surfaces.csv" "$D/$4/"
  for L in "$T"/levels/*; do mkdir -p "$D/$4/levels/${L##*/}"; cp "$L/summary.json" "$L/surfaces.csv" "$D/$4/levels/${L##*/}/"; done
  rm -rf "$T"
}
( ref aligned 24 two aligned_two; ref alternating 24 two alternating_two; ref alternating 48 two alternating48_two --min-levels 5 ) &
( ref aligned 24 one aligned_one; ref alternating 24 one alternating_one; ref alternating 48 one alternating48_one --min-levels 5 ) &
wait
inv() {  # diagonals two_sided
  PYTHONPATH=build/python $PY scripts/lattice_inversion.py cylinder_press --set "effects=$EFF" \
    --set bodies.0.material.bulk_modulus=10000 --set "bodies.0.shape.diagonals=\"$1\"" \
    --set contacts.0.two_sided=$2 --set 'contacts.0.detector="cgal"' --set 'contacts.0.eliminator="line"' \
    --set 'contacts.0.force={"stiffness":500}' --out "$D/inv_$1_$2.csv"
}
( inv aligned true; inv alternating true ) &
( inv aligned false; inv alternating false ) &
wait
{ echo "diagonals,two_sided,$(head -1 "$D/inv_aligned_true.csv")"
  for d in aligned alternating; do for t in true false; do tail -n +2 "$D/inv_${d}_$t.csv" | sed "s/^/$d,$t,/"; done; done
} > "$D/inversion.csv"
rm -f "$D"/inv_*.csv
inv48() {  # two_sided
  PYTHONPATH=build/python $PY scripts/lattice_inversion.py cylinder_press --set "effects=$EFF" \
    --set bodies.0.material.bulk_modulus=10000 --set 'bodies.0.shape.diagonals="alternating"' \
    --set bodies.1.shape.segments=48 --set contacts.0.two_sided=$1 --set 'contacts.0.detector="cgal"' \
    --set 'contacts.0.eliminator="line"' --set 'contacts.0.force={"stiffness":500}' --out "$D/inv48_$1.csv"
}
inv48 true & inv48 false & wait
{ echo "two_sided,$(head -1 "$D/inv48_true.csv")"
  for t in true false; do tail -n +2 "$D/inv48_$t.csv" | sed "s/^/$t,/"; done
} > "$D/inversion48.csv"
rm -f "$D"/inv48_*.csv
# Committed form (results/README.md): steps.csv.gz, level and run surfaces gzipped.
${PYTHON:-/usr/bin/python3} scripts/store_results.py results/cylinder_bulk
