#!/usr/bin/env bash
# End-to-end checks of the command line: outputs, exit statuses, one-line errors,
# and that bad input leaves an earlier run's outputs untouched.
# Usage: test_cli.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0; pass=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL: $*"; fail=$((fail+1)); }

# --help and list
"$H" --help >/dev/null 2>&1 && ok || bad "--help"
"$H" list > "$T/list.txt" 2>&1 && grep -q cylinder_press "$T/list.txt" && ok || bad "list shows cylinder_press"

# A good run writes the three outputs.
"$H" run cylinder_press --out "$T/run" --steps 20 --set output.frames_every=10 --quiet 2>"$T/err" \
  && ok || { bad "run cylinder_press"; cat "$T/err"; }
[[ -f "$T/run/steps.csv" && -f "$T/run/summary.json" ]] && ok || bad "outputs written"
# The contract's columns in order, the wall times (t_*_us) in timing.csv keyed by step and pair.
head -1 "$T/run/steps.csv" | grep -q '^step,time,pair,detector,contacts,kinetic_energy,true_pen_guest,true_pen_host,tp,fp,fn,max_depth,mean_depth,surfaces_intersect,fcl_pairs' \
  && ok || bad "steps.csv columns"
head -1 "$T/run/timing.csv" | grep -q '^step,pair,t_step_us,t_physics_us,t_detect_us,t_eliminate_us,t_cgal_us,t_fcl_us' \
  && ok || bad "timing.csv columns"
head -1 "$T/run/steps.csv" | grep -q '_us\b' && bad "a wall time in steps.csv" || ok
[[ $(($(wc -l < "$T/run/steps.csv") - 1)) -eq 20 ]] && ok || bad "one row per step and pair"
[[ $(wc -l < "$T/run/timing.csv") -eq $(wc -l < "$T/run/steps.csv") ]] && ok || bad "timing.csv: a row per steps.csv row"
ls "$T/run/frames/" | grep -q '_000000.vtp' && ls "$T/run/frames/" | grep -q '_000020.vtp' && ok || bad "frames at 0 and last step"
[[ -f "$T/run/frames/layer.pvd" && $(grep -c "<DataSet" "$T/run/frames/layer.pvd") -eq 3 ]] && ok || bad "layer.pvd lists 3 frames"
grep -q '"status": "ok"' "$T/run/summary.json" && ok || bad "summary status ok"
for k in scene status error steps_run finite effects git_commit versions resolved_scene state_hash timing_us pairs; do
  grep -q "\"$k\"" "$T/run/summary.json" && ok || bad "summary key $k"
done
f=$(ls "$T"/run/frames/*_000000.vtp | head -1)
grep -q 'type="PolyData"' "$f" && grep -q 'Name="signed_distance"' "$f" && ok || bad "VTK XML polydata"
# output.format "vtk": the legacy ASCII frames, no collection.
"$H" run cylinder_press --out "$T/legacy" --steps 20 --set output.frames_every=10 --set output.format=vtk --quiet \
  && f=$(ls "$T"/legacy/frames/*_000000.vtk | head -1) && head -5 "$f" | grep -q "DATASET POLYDATA" \
  && grep -q "^POLYGONS" "$f" && ! ls "$T"/legacy/frames/*.pvd >/dev/null 2>&1 && ok || bad "legacy VTK polydata"
# --dt S runs the scene at time step S over the same physical time: the same state as --dt-divide
# with the same factor (every step count scaled from the key table); a step that is not positive
# is refused.
"$H" run cylinder_press --out "$T/div" --steps 10 --dt-divide 2 --set 'references.solvers=[]' --quiet \
  && "$H" run cylinder_press --out "$T/dt" --steps 10 --dt 2.5e-5 --set 'references.solvers=[]' --quiet \
  && [[ "$(grep -o '"state_hash": "[0-9a-f]*"' "$T/div/summary.json")" == "$(grep -o '"state_hash": "[0-9a-f]*"' "$T/dt/summary.json")" ]] \
  && grep -q '"steps_run": 20' "$T/dt/summary.json" && ok || bad "--dt equals --dt-divide"
# --dt not a divisor of the scene's dt: every count rounded (10 steps of 5e-5 s: 17 of 3e-5 s).
"$H" run cylinder_press --out "$T/dt3" --steps 10 --dt 3e-5 --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 0 ]] && grep -q '"steps_run": 17' "$T/dt3/summary.json" && ok || bad "--dt not a divisor: exit $rc"
# ... and each rounded count of the forcing (the cylinder's driver) is a warning naming its key (stderr and
# summary.json), refused with --strict; the run's own counts (time.steps) round silently; a whole divisor
# rounds nothing
grep -q "warning: --dt: bodies.1.drivers.0.to_step: 4000 steps at the scene's time.dt are 6666.67 at --dt, rounded to 6667" "$T/err" \
  && grep -q -- '"--dt: bodies.1.drivers.0.to_step: 4000 steps' "$T/dt3/summary.json" && ! grep -q -- '"--dt: ' "$T/dt/summary.json" \
  && ! grep -q -- "--dt: time.steps" "$T/err" \
  && ok || { bad "--dt rounding warning"; cat "$T/err"; }
"$H" run cylinder_press --out "$T/dt3s" --steps 10 --dt 3e-5 --quiet --strict 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 && ! -e "$T/dt3s/summary.json" ]] && grep -q -- "--dt: bodies.1.drivers.0.to_step" "$T/err" \
  && ok || { bad "--dt rounding with --strict: exit $rc"; cat "$T/err"; }
"$H" run cylinder_press --out "$T/dt0" --steps 10 --dt 0 --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && grep -q -- "--dt" "$T/err" && ok || bad "--dt 0: exit $rc"
# harness schema prints the scene format's JSON Schema.
"$H" schema | grep -q '"$schema": "https://json-schema.org/draft/2020-12/schema"' && ok || bad "harness schema"

# Bad inputs: exit 2, exactly one line on stderr naming the file, nothing touched.
cp "$T/run/summary.json" "$T/summary.before"
bad_case() {  # name, expected substring, scene text
  local name="$1" expect="$2"
  printf '%s' "$3" > "$T/$name.json"
  "$H" run "$T/$name.json" --out "$T/run" --quiet 2>"$T/err" >/dev/null
  local rc=$?
  [[ $rc -eq 2 ]] && ok || bad "$name: exit $rc, expected 2"
  [[ $(wc -l < "$T/err") -eq 1 ]] && ok || { bad "$name: stderr not one line"; cat "$T/err"; }
  grep -q -- "$expect" "$T/err" && ok || { bad "$name: message lacks '$expect'"; cat "$T/err"; }
  cmp -s "$T/run/summary.json" "$T/summary.before" && ok || bad "$name: earlier summary changed"
}
good='{"name":"g","time":{"dt":1e-4,"steps":2},"effects":["springs"],"bodies":[{"name":"a","shape":{"type":"sphere","radius":0.01,"subdivisions":1}}]}'
bad_case malformed "malformed.json:1:" '{"name": "x",'
bad_case unknown "unknown.json: bodies.0.colour: unknown key" "${good/\"name\":\"a\"/\"name\":\"a\",\"colour\":1}"
bad_case dt "dt.json: time.dt" "${good/1e-4/-1}"
bad_case steps "steps.json: time.steps" "${good/\"steps\":2/\"steps\":-2}"
"$H" run "$T/nonexistent.json" --out "$T/run" --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q "nonexistent.json" "$T/err" && ok || bad "missing scene file: exit $rc"
"$H" run cylinder_press --out "$T/run" --set time.dt=abc --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q -- "time.dt" "$T/err" && ok || bad "bad --set: exit $rc"
"$H" run cylinder_press --out "$T/run" --set 'time.dt={x' --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q -- "--set time.dt: value is not valid JSON" "$T/err" && ok || bad "--set not JSON: exit $rc"
HARNESS_THREADS=abc "$H" run cylinder_press --out "$T/run" --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q "HARNESS_THREADS" "$T/err" && ok || bad "HARNESS_THREADS=abc: exit $rc"
# A run logged to a file (not a terminal): a line every tenth of the steps and an end-of-run line.
"$H" run cylinder_press --out "$T/logged" --steps 40 --set 'references.solvers=[]' 2>"$T/log" \
  && grep -q "step 20/40.*50 %" "$T/log" && grep -q "step 40/40.*100 %" "$T/log" \
  && tail -1 "$T/log" | grep -q "cylinder_press: ok, 40 steps.*$T/logged" && ok || { bad "progress log lines"; cat "$T/log"; }
# An output folder that cannot be made: exit 2 naming it.
touch "$T/plainfile"
"$H" run cylinder_press --out "$T/plainfile/sub" --steps 2 --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q -- "--out $T/plainfile/sub" "$T/err" && ok || { bad "unwritable --out: exit $rc"; cat "$T/err"; }
# A bare word is a string for --set, as for --grid.
"$H" run cylinder_press --out "$T/bare" --steps 2 --set contacts.0.eliminator=plane --set 'references.solvers=[]' \
  --quiet 2>"$T/err" && grep -q '"eliminator": "plane"' "$T/bare/summary.json" && ok || { bad "--set bare word"; cat "$T/err"; }
# SIGINT / SIGTERM: the run stops after the current step, writes its outputs with status
# "interrupted" and exits 130 / 143.
for sig in INT TERM; do
  "$H" run cylinder_press --out "$T/sig$sig" --steps 1000000 --set 'references.solvers=[]' 2>"$T/err" &
  pid=$!
  for _ in $(seq 100); do [[ -s "$T/sig$sig/steps.csv" ]] && break; sleep 0.1; done
  sleep 0.5; kill -s "$sig" "$pid"; wait "$pid"; rc=$?
  want=$([[ $sig == INT ]] && echo 130 || echo 143)
  [[ $rc -eq $want ]] && grep -q '"status": "interrupted"' "$T/sig$sig/summary.json" 2>/dev/null \
    && tail -1 "$T/err" | grep -q "interrupted" && ok || { bad "SIG$sig: exit $rc (expected $want)"; tail -3 "$T/err"; }
done
# Warnings: a voxel size rounded to a power of two says from and to; --strict makes it exit 2
# before anything is written.
"$H" run cylinder_press --out "$T/warn" --steps 2 --set 'contacts.0.detector="voxel"' --set contacts.0.voxel_size=0.005 \
  --set 'references.solvers=[]' --quiet 2>"$T/err" && grep -q "warning: contacts.0.voxel_size: 0.005 m rounded down to a power of two: 0.00390625 m" "$T/err" \
  && grep -q "rounded down" "$T/warn/summary.json" && ok || { bad "voxel rounding warning"; cat "$T/err"; }
"$H" run cylinder_press --out "$T/strict" --steps 2 --set 'contacts.0.detector="voxel"' --set contacts.0.voxel_size=0.005 \
  --set 'references.solvers=[]' --quiet --strict 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 && ! -e "$T/strict/summary.json" ]] && grep -q "cylinder_press.json: contacts.0.voxel_size" "$T/err" \
  && ok || { bad "--strict: exit $rc"; cat "$T/err"; }
# Tunnelling: hard/fast_impact's ball (2.4 mm node spacing, 2 mm voxels) crosses the layer; the
# start warns that it is expected, the end counts the tunnelled nodes (warning, summary, end line).
"$H" run hard/fast_impact --out "$T/tunnel" 2>"$T/err"
grep -q "warning: contacts.0: guest 'ball' node spacing .* coarser than the voxel" "$T/err" \
  && grep -q "warning: contacts.0: [1-9][0-9]* guest nodes tunnelled" "$T/err" && tail -1 "$T/err" | grep -q "[1-9][0-9]* tunnelled" \
  && tail -1 "$T/err" | grep -q ", [a-z]* but tunnels" \
  && grep -q '"tunnelled": [1-9]' "$T/tunnel/summary.json" && ok || { bad "tunnelling warnings"; cat "$T/err"; }
"$H" run cylinder_press --out "$T/run" --bogus 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && ok || bad "unknown option: exit $rc"
cmp -s "$T/run/summary.json" "$T/summary.before" && ok || bad "summary survived bad inputs"

# harness sweep: product of grids, --list, --index, runs.csv; bad grid values are bad input.
"$H" sweep sphere_collision --grid contacts.0.force=0.01,auto --grid contacts.0.eliminator=line,plane \
  --set time.steps=5 --set time.settle=null --set 'references.solvers=[]' --set output.frames_every=0 --out "$T/sw" -j 2 2>/dev/null \
  && ok || bad "sweep runs"
[[ $(($(wc -l < "$T/sw/runs.csv") - 1)) -eq 4 ]] && ok || bad "sweep runs.csv has 4 rows"
head -1 "$T/sw/runs.csv" | grep -q '^point,name,no_force,contacts.0.force,contacts.0.eliminator,status,stability,contact_power_ratio,' \
  && head -1 "$T/sw/runs.csv" | grep -q ',tunnelled_guest,tunnelled_host,.*,error_window_mean,error_window_max,error_window_chatter,.*,no_force_error,helps,useless$' \
  && ok || bad "runs.csv header"
# --baseline: one no-force run (every pair's force 0) per combination of the grid's values outside
# contacts.*; with --compare each point says whether it helps (the rule recomputed here from the
# row's own figures) and what makes it useless.
"$H" sweep sphere_collision --grid contacts.0.force=0.003,0.03 --grid time.window=200,300 --set time.steps=1200 \
  --set time.settle=null --set 'contacts.0.detector="voxel"' --set contacts.0.two_sided=false --set output.frames_every=0 \
  --baseline --compare "$SRC/results/references/sphere_collision" --out "$T/swb" -j 2 2>/dev/null && ok || bad "sweep --baseline"
[[ -f "$T/swb/no_force__time.window-200/summary.json" && -f "$T/swb/no_force__time.window-300/summary.json" \
   && $(($(wc -l < "$T/swb/runs.csv") - 1)) -eq 6 ]] && ok || bad "sweep --baseline: 4 points and 2 no-force runs"
[[ $("$H" sweep sphere_collision --grid contacts.0.force=0.003,0.03 --grid time.window=200,300 --baseline --out "$T/swb2" --list \
     | grep -c "contacts.0.force=0$") -eq 2 ]] && ok || bad "sweep --baseline --list lists the no-force runs"
"${PYTHON:-/usr/bin/python3}" - "$T/swb/runs.csv" <<'EOF' && ok || bad "runs.csv helps/useless"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
base = {r["time.window"]: r for r in rows if r["no_force"] == "1"}
assert len(base) == 2 and all(r["helps"] == "" for r in base.values())
for r in rows:
    if r["no_force"] == "1":
        continue
    b = base[r["time.window"]]
    err, berr = float(r["error_window_mean"]), float(b["error_window_mean"])
    d, bd = float(r["depth_window_max"]), float(b["depth_window_max"])
    assert float(r["no_force_error"]) == berr
    helps = err <= 0.9 * berr or (d <= 0.9 * bd and err <= berr)
    assert r["helps"] == ("yes" if helps else "no"), r
    tun = int(r["tunnelled_guest"]) + int(r["tunnelled_host"])
    want = "; ".join((["tunnels"] if tun else []) + ([] if helps else ["no better than no force"]))
    assert r["useless"] == want, (r["useless"], want)
    assert r["stability"] and float(r["error_window_chatter"]) >= 0
EOF
[[ -f "$T/sw/contacts.0.force-auto__contacts.0.eliminator-plane/summary.json" ]] && ok || bad "point folder named by parameters"
[[ $("$H" sweep sphere_collision --grid contacts.0.force=0.01,auto --grid contacts.0.eliminator=line,plane --out "$T/sw2" --list | wc -l) -eq 4 ]] \
  && ok || bad "sweep --list prints 4 commands"
"$H" sweep sphere_collision --grid contacts.0.force=0.01,auto --set time.steps=5 --set time.settle=null --set 'references.solvers=[]' --out "$T/sw3" --index 1 2>/dev/null \
  && [[ -f "$T/sw3/contacts.0.force-auto/summary.json" && ! -e "$T/sw3/contacts.0.force-0.01" ]] && ok || bad "sweep --index 1"
"$H" sweep sphere_collision --grid contacts.0.force=-1 --out "$T/sw4" 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q "contacts.0.force" "$T/err" && [[ ! -e "$T/sw4" ]] && ok || bad "sweep bad value: exit $rc"

# harness list: the steps a scene runs, and its settling cap
"$H" list | grep -q "^cylinder_press .* 5000 steps then settling, up to 30000 more" && ok || bad "list: steps and settle cap"
# harness reference: the end line says what it knows (floor, order, estimate); summary.json records the floor
"$H" reference hard/collinear_plane --max-levels 3 --min-levels 3 --out "$T/ref" 2>"$T/err"
grep -q "^reference: .*after 3 levels; floor [0-9.e+-]* mm (.*), observed order " "$T/err" && ok \
  || { bad "reference end line"; cat "$T/err"; }
/usr/bin/python3 - "$T/ref/summary.json" "$2/scripts" <<'PY' && ok || bad "reference floor in summary.json: the scripts' rule"
import json, sys
sys.path.insert(0, sys.argv[2])
from harness_results import reader
s = json.load(open(sys.argv[1]))
r = dict(s, reference=dict(s["reference"], floor=None))  # the rule the scripts apply without it
sys.exit(0 if abs(reader.reference_floor(r)[0] - s["reference"]["floor"]) <= 0 else 1)
PY

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
