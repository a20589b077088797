#!/usr/bin/env bash
# A two-point sweep through the Snakemake workflow, locally (-j 2): one job per point, then
# the merge; runs.csv must hold both points, as `harness sweep` would write it.
# Usage: test_snakemake.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
SNAKEMAKE=$(command -v snakemake || echo /usr/bin/snakemake)
if [[ ! -x "$SNAKEMAKE" ]]; then echo "0 passed, 1 failed"; echo "FAIL: snakemake not installed (scripts/install-deps.sh installs it)"; exit 1; fi
pass=0; fail=0
"$SNAKEMAKE" -s "$SRC/experiments/Snakefile" -j 2 --directory "$T" --quiet \
  --config scene=sphere_collision "harness=$H" "out=$T/sweep" \
  'grid=["contacts.0.eliminator=line,plane"]' \
  'set=["time.steps=20","references.solvers=[]","output.frames_every=0"]' > "$T/log" 2>&1
rc=$?
[[ $rc -eq 0 ]] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL: snakemake exit $rc"; tail -20 "$T/log"; }
rows=$(($(wc -l < "$T/sweep/runs.csv" 2>/dev/null || echo 0) - 1))
[[ $rows -eq 2 ]] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL: runs.csv has $rows rows, expected 2"; }
for p in contacts.0.eliminator-line contacts.0.eliminator-plane; do
  grep -q '"status": "ok"' "$T/sweep/$p/summary.json" 2>/dev/null && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL: $p"; }
done
# The same sweep by the program alone gives the same state hashes (the workflow adds nothing).
"$H" sweep sphere_collision --grid contacts.0.eliminator=line,plane --set time.steps=20 \
  --set 'references.solvers=[]' --set output.frames_every=0 --out "$T/direct" -j 2 2>/dev/null
if [[ "$(cut -d, -f7 "$T/sweep/runs.csv")" == "$(cut -d, -f7 "$T/direct/runs.csv")" ]]; then pass=$((pass+1)); else fail=$((fail+1)); echo "FAIL: hashes differ"; fi
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
