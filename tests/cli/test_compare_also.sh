#!/usr/bin/env bash
# `harness run --compare A --compare-also B`: the second reference is measured on the same steps as
# the first and changes nothing else: the run's state and its figures against A are those of a run
# with --compare A alone, and its figures against B (summary error_vs_reference_also, steps.csv
# also_* columns) are those of a run with --compare B. --compare-also without --compare, or a folder
# that is not a reference, is bad input (exit 2).
# Usage: test_compare_also.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
A="$SRC/results/references/sphere_collision"
B="$SRC/results/references/sphere_collision_one_sided"
[ -f "$A/surfaces.csv" ] && [ -f "$B/surfaces.csv" ] || { echo "SKIP: no references"; exit 77; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
# 600 steps of the sphere collision with the paper's voxel model one way: the spheres touch, the
# references differ (one way against both ways), CGAL every 10 steps.
S=(--steps 600 --quiet --set references.every=10 --set 'contacts.0.detector="voxel"' --set contacts.0.two_sided=false)
"$H" run sphere_collision "${S[@]}" --out "$T/a" --compare "$A" || fail "run --compare A exited $?"
"$H" run sphere_collision "${S[@]}" --out "$T/b" --compare "$B" || fail "run --compare B exited $?"
"$H" run sphere_collision "${S[@]}" --out "$T/ab" --compare "$A" --compare-also "$B" || fail "run --compare-also exited $?"
"$PY" - "$T" <<'PYEOF' || fail "figures differ"
import csv, json, sys
T = sys.argv[1]
s = {k: json.load(open("%s/%s/summary.json" % (T, k))) for k in ("a", "b", "ab")}
assert s["ab"]["state_hash"] == s["a"]["state_hash"], "the second reference changed the run"
ea, eb = s["a"]["pairs"][0]["error_vs_reference"], s["b"]["pairs"][0]["error_vs_reference"]
first, also = s["ab"]["pairs"][0]["error_vs_reference"], s["ab"]["pairs"][0]["error_vs_reference_also"]
assert first == ea, "figures against the first reference changed"
for k in ("pos_err_max", "pos_err_rms", "gap_max", "gap_mean"):
    assert also[k] == eb[k], (k, also[k], eb[k])
    assert also["window"][k] == eb["window"][k], (k, also["window"][k], eb["window"][k])
assert also["window"]["pos_err_max"]["mean"] != ea["window"]["pos_err_max"]["mean"], "the two references agree"
rows = lambda k: list(csv.DictReader(open("%s/%s/steps.csv" % (T, k))))
rb, rab = rows("b"), rows("ab")
n = 0
for x, y in zip(rb, rab):
    for c in ("pos_err_max", "gap_max"):
        assert x[c] == y["also_" + c], (x["step"], c, x[c], y["also_" + c])
    n += x["pos_err_max"] != ""
assert n >= 50, n
assert all(r["also_pos_err_max"] == "" for r in rows("a")), "also_ columns without a second reference"
PYEOF
"$H" run sphere_collision --steps 5 --quiet --out "$T/x" --compare-also "$B" 2>"$T/err"; rc=$?
[ $rc -eq 2 ] && grep -q -- "--compare-also" "$T/err" || fail "--compare-also alone: exit $rc, $(cat "$T/err")"
"$H" run sphere_collision --steps 5 --quiet --out "$T/y" --compare "$A" --compare-also "$T/none" 2>"$T/err"; rc=$?
[ $rc -eq 2 ] && grep -q -- "--compare-also $T/none" "$T/err" || fail "--compare-also not a reference: exit $rc, $(cat "$T/err")"
# scripts/runs_compare_also.py adds the second reference to a finished run without making it again in
# its folder: run A's folder gains what the run with --compare-also measured against B; a folder whose
# rerun ends in another state (its recorded hash altered) is left untouched, exit 1.
mkdir -p "$T/runs" "$T/refs"
cp -r "$T/a" "$T/runs/a"
ln -s "$(cd "$A" && pwd)" "$T/refs/sphere_collision"; ln -s "$(cd "$B" && pwd)" "$T/refs/sphere_collision_one_sided"
"$PY" "$SRC/scripts/runs_compare_also.py" "$T/runs" --harness "$H" --references "$T/refs" -j 1 >"$T/out" 2>&1 \
  || fail "runs_compare_also exited $?: $(cat "$T/out")"
"$PY" - "$T" <<'PYEOF' || fail "runs_compare_also wrote other figures than --compare-also measures"
import json, sys
T = sys.argv[1]
got, ab, a = (json.load(open("%s/%s/summary.json" % (T, k))) for k in ("runs/a", "ab", "a"))
also, want = got["pairs"][0]["error_vs_reference_also"], ab["pairs"][0]["error_vs_reference_also"]
for k in ("pos_err_max", "pos_err_rms", "gap_max", "gap_mean", "window"):
    assert also[k] == want[k], k
assert got["state_hash"] == a["state_hash"] and got["timing_us"] == a["timing_us"]
assert got["pairs"][0]["error_vs_reference"] == a["pairs"][0]["error_vs_reference"]
assert got["compare_also"]["reference"].endswith("sphere_collision_one_sided")
PYEOF
cp -r "$T/a" "$T/runs/c"
"$PY" - "$T/runs/c/summary.json" <<'PYEOF'
import json, sys
s = json.load(open(sys.argv[1])); s["state_hash"] = "0" * 16
json.dump(s, open(sys.argv[1], "w"))
PYEOF
cp "$T/runs/c/summary.json" "$T/c.json"
"$PY" "$SRC/scripts/runs_compare_also.py" "$T/runs" --only c --harness "$H" --references "$T/refs" -j 1 >"$T/out" 2>&1; rc=$?
[ $rc -eq 1 ] && grep -q "another state" "$T/out" && cmp -s "$T/c.json" "$T/runs/c/summary.json" \
  || fail "a run that does not reproduce: exit $rc, $(cat "$T/out")"
[ $fails -eq 0 ] && echo "compare-also: ok"
exit $fails
