#!/usr/bin/env bash
# The stability class is the scene's physics, not its loading's pace (core/run/window.hpp): the
# bundled cylinder pressed into the layer, and the same scene with its loading ramp twice as slow
# (the driver's velocity halved, its steps doubled: the same travel), get the same class for a
# stable exact run (CGAL and the scene's penalty: settles) and for a chattering run of the paper's
# model (voxel grid, line, automatic force: its nodes move about 2 mm over the final window, below
# its 8 mm voxel: steady). The earlier rate (rho over the loading period, still recorded) moved with
# the pace (1.11 against 1.91 when this was written): the test also asserts that it is not what
# decides. Usage: test_stability_class.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
run() {
  local name="$1"; shift
  HARNESS_THREADS=1 "$H" run cylinder_press --out "$T/$name" --quiet --set 'references.solvers=[]' \
    --set output.frames_every=0 "$@" 2>"$T/$name.err" || { echo "FAIL: run $name: $(head -1 "$T/$name.err")"; return 1; }
}
slow=(--set 'bodies.1.drivers.0.velocity=[0,0,-0.025]' --set bodies.1.drivers.0.to_step=8000
      --set bodies.1.drivers.1.from_step=8001 --set time.steps=9000)
voxel=(--set 'contacts.0.detector="voxel"' --set 'contacts.0.force="auto"' --set contacts.0.two_sided=false)
ok=0
{ run exact & run exact_slow "${slow[@]}" & wait; } || ok=1
{ run voxel "${voxel[@]}" & run voxel_slow "${voxel[@]}" "${slow[@]}" & wait; } || ok=1
"$PY" - "$T" <<'PYEOF'
import json, sys
T = sys.argv[1]
s = {k: json.load(open("%s/%s/summary.json" % (T, k))) for k in ("exact", "exact_slow", "voxel", "voxel_slow")}
passed = failed = 0
def check(ok, what):
    global passed, failed
    passed += ok
    failed += not ok
    if not ok:
        print("FAIL: " + what)
v = {k: x["stability_verdict"] for k, x in s.items()}
w = {k: x["window"] for k, x in s.items()}
check(v["exact"] == v["exact_slow"] and v["exact"] in ("settled", "steady"), "exact runs: %s / %s" % (v["exact"], v["exact_slow"]))
check(v["voxel"] == v["voxel_slow"], "voxel runs: %s / %s" % (v["voxel"], v["voxel_slow"]))
for k in ("voxel", "voxel_slow"):
    amp = w[k]["chatter_amplitude_m"]
    check(amp is not None and amp > 1e-3, "%s: a chattering run (amplitude %s m)" % (k, amp))
    check(w[k]["chatter_length_from"] == "voxel", "%s: its length is the voxel (%s)" % (k, w[k]["chatter_length_from"]))
# the time scale is the scene's, not the loading's
check(w["voxel"]["time_scale_s"] == w["voxel_slow"]["time_scale_s"], "time scales differ")
# the earlier rate moved with the pace; the class did not follow it
r = w["voxel_slow"]["contact_power_ratio"] / w["voxel"]["contact_power_ratio"]
check(r > 1.3, "rho moved %.2fx with the pace: this test no longer shows what it argues" % r)
check(abs(w["voxel"]["contact_input_share"] - w["voxel_slow"]["contact_input_share"]) <
      0.5 * max(w["voxel"]["contact_input_share"], 1e-12), "contact input shares %s / %s" %
      (w["voxel"]["contact_input_share"], w["voxel_slow"]["contact_input_share"]))
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
PYEOF
rc=$?
exit $(( rc || ok ))
