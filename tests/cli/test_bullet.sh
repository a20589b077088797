#!/usr/bin/env bash
# `harness run --engine bullet`: the Bullet variants of sphere_collision and cylinder_press run and
# write the same outputs (steps.csv with the engine's contact model and contact counts, summary.json
# with "engine", frames with the contact force NaN); what Bullet cannot represent is refused with
# exit 2 naming the key, before anything is written; bad engine options are exit 2.
# Usage: test_bullet.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
expect2() {  # expect2 NAME PATTERN ARGS...: exit 2, one line naming PATTERN, no summary written
  local name="$1" pat="$2"; shift 2
  "$H" run "$@" --out "$T/$name" --quiet 2>"$T/$name.err"; local rc=$?
  [[ $rc -eq 2 ]] || fail "$name: exit $rc, expected 2 ($(head -1 "$T/$name.err"))"
  grep -q -- "$pat" "$T/$name.err" || fail "$name: message does not name $pat: $(head -1 "$T/$name.err")"
  [[ $(wc -l <"$T/$name.err") -eq 1 ]] || fail "$name: more than one line on stderr"
  [[ ! -e "$T/$name/summary.json" ]] || fail "$name: a summary was written"
}
expect2 law "bodies.0.material.law" sphere_collision --engine bullet
expect2 dashpot "bodies.1.material.damping" "$SRC/experiments/scenes/bullet/cylinder_press.json" --engine bullet \
  --set bodies.1.material.damping=0.002
expect2 pressure "bodies.1.pressure" implant_expansion --engine bullet --set bodies.0.material.law=linear \
  --set bodies.0.material.damping=0 --set bodies.1.material.damping=0
expect2 engine "--engine" bullet/sphere_collision --engine physx
expect2 margin_alone "--bullet-margin" bullet/sphere_collision --bullet-margin 0.001
expect2 margin_negative "--bullet-margin" bullet/sphere_collision --engine bullet --bullet-margin -1
expect2 iterations "--bullet-iterations" bullet/sphere_collision --engine bullet --bullet-iterations 0

for n in sphere_collision cylinder_press; do
  "$H" run "bullet/$n" --engine bullet --steps 300 --set output.frames_every=300 --set references.every=100 \
    --bullet-margin 0.0002 --out "$T/$n" --quiet 2>"$T/$n.err" || { fail "bullet/$n: exit $? ($(tail -1 "$T/$n.err"))"; continue; }
done
"$PY" - "$T" <<'PYEOF' || fails=$((fails + 1))
import csv, json, math, os, sys, xml.etree.ElementTree as ET
T = sys.argv[1]; bad = 0
def check(c, what):
    global bad
    if not c: bad += 1; print("FAIL:", what)
for n in ["sphere_collision", "cylinder_press"]:
    d = os.path.join(T, n)
    if not os.path.exists(os.path.join(d, "summary.json")):
        check(False, n + ": no summary"); continue
    s = json.load(open(os.path.join(d, "summary.json")))
    e = s.get("engine", {})
    check(s["status"] == "ok" and s["steps_run"] == 300, n + ": status %s, %s steps" % (s["status"], s["steps_run"]))
    check(e.get("name") == "bullet" and e.get("margin_m") == [0.0002, 0.0002], n + ": engine %s" % e)
    check(e.get("version", "").endswith("(double)") and "Bullet" in s["versions"], n + ": Bullet's double build recorded")
    check(s["pairs"][0]["detector"] == "bullet_vf_ss", n + ": pair detector %s" % s["pairs"][0]["detector"])
    check(s["energy"]["work_contact"] is None and s["energy"]["energy_kinetic"] > 0, n + ": energies without booked work")
    rows = list(csv.DictReader(open(os.path.join(d, "steps.csv"))))
    check(len(rows) == 300 and all(r["detector"] == "bullet_vf_ss" for r in rows), n + ": steps.csv detector column")
    timing = list(csv.DictReader(open(os.path.join(d, "timing.csv"))))
    check(all(r["contacts"] != "" for r in rows) and len(timing) == len(rows) and all(t["t_detect_us"] != "" for t in timing),
          n + ": contacts and detection time (timing.csv) each step")
    check(sum(r["true_pen_guest"] != "" for r in rows) >= 3, n + ": the references measured the engine's states")
    frames = sorted(f for f in os.listdir(os.path.join(d, "frames")) if f.endswith(".vtp"))
    check(len(frames) == 4, n + ": frames %s" % frames)
print("bullet outputs: %d failures" % bad)
sys.exit(1 if bad else 0)
PYEOF
[[ $fails -eq 0 ]] && echo "test_bullet: all checks passed" || { echo "test_bullet: $fails failing"; exit 1; }
