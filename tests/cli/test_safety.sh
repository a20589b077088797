#!/usr/bin/env bash
# Safety on long jobs (docs/usage.md): a run past --max-wall stops as failed and says so, with its
# outputs written (exit 3, summary status "error", the state finite, steps.csv up to the last step);
# a step that needs more than time.max_substeps is refused at load (exit 2 naming the key); a step
# that fails after a blow-up names the blow-up first; harness sweep passes its --max-wall to every
# point (--list shows it).
# Usage: test_safety.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# --max-wall: the implant's full run takes minutes; stopped after 1 s.
HARNESS_THREADS=1 "$H" run implant_expansion --out "$T/wall" --quiet --max-wall 1 --set 'references.solvers=[]' 2>"$T/err"; rc=$?
"$PY" - "$T/wall" "$rc" <<'PYEOF' || bad "--max-wall: $(cat "$T/err")"
import csv, json, sys
d, rc = sys.argv[1], int(sys.argv[2])
s = json.load(open(d + "/summary.json"))
rows = sum(1 for _ in csv.reader(open(d + "/steps.csv"))) - 1
assert rc == 3, rc
assert s["status"] == "error" and "--max-wall" in s["error"], s["error"]
assert s["finite"] is True, s["finite"]
assert 0 < s["steps_run"] < 26000 and rows == s["steps_run"], (s["steps_run"], rows)
PYEOF
"$H" run implant_expansion --out "$T/w2" --quiet --max-wall -1 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q -- "--max-wall" "$T/err" || bad "--max-wall -1: exit $rc $(cat "$T/err")"

# time.max_substeps: the spheres at dt = 1 ms under guard "substep" need about 20 substeps at rest;
# a cap of 2 refuses them at load, the default cap (1000) runs them.
sub=(--steps 5 --set time.dt=0.001 --set 'time.guard="substep"' --set 'references.solvers=[]')
"$H" run sphere_collision --out "$T/sub" --quiet "${sub[@]}" --set time.max_substeps=2 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q "time.max_substeps" "$T/err" || bad "time.max_substeps=2: exit $rc $(cat "$T/err")"
"$H" run sphere_collision --out "$T/sub2" --quiet "${sub[@]}" 2>"$T/err"; rc=$?
[[ $rc -eq 0 ]] || bad "the default cap: exit $rc $(cat "$T/err")"

# A blow-up: a constant force of 1000 N per contact (the hard case's 5 N times 200) throws the
# layer apart within six steps; the step then fails on the voxel region's size, and the message
# names the blow-up first (measured: the layer spans 2.1e5 times its rest size).
"$H" run force_100x --out "$T/blow" --quiet --set contacts.0.force=1000 --set 'references.solvers=[]' 2>"$T/err"; rc=$?
if [[ $rc -eq 3 ]]; then
  grep -q "simulation failed: step [0-9]*: blow-up: body layer spans .* times its rest size; then: .*voxel region" "$T/err" \
    || bad "blow-up not named first: $(grep 'failed' "$T/err")"
else
  bad "force 1e6 N: exit $rc, expected a failed run (3): $(tail -1 "$T/err")"
fi

# harness sweep passes its cap to every point.
"$H" sweep sphere_collision --grid contacts.0.force=0.001,0.002 --out "$T/sw" --list --max-wall 77 >"$T/list" 2>&1 \
  && [[ $(grep -c -- "--max-wall 77" "$T/list") -eq 2 ]] || bad "sweep --list: $(cat "$T/list")"
"$H" sweep sphere_collision --grid contacts.0.force=0.001 --out "$T/sw2" --list >"$T/list2" 2>&1 \
  && grep -q -- "--max-wall 1800" "$T/list2" || bad "sweep default cap: $(cat "$T/list2")"
[[ $fails -eq 0 ]] && echo "safety: all checks passed" || exit 1
