#!/usr/bin/env bash
# What a run says about itself, end to end: the stability verdict over the final window (a ball
# dropped on a layer that the paper's voxel model kicks away warns, --strict exits 2 after writing
# its outputs; the same drop with the conservative penalty does not), and a reference with a
# non-finite node is refused naming the node.
# Usage: test_footing.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0; pass=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL: $*"; fail=$((fail+1)); }
PY="${PYTHON:-/usr/bin/python3}"

# A ball dropped 2 mm onto a pinned layer. Voxel model, plane rule, a constant 0.05 N per contact:
# the contact launches the ball, which leaves with the energy it was given.
cat > "$T/drop.json" <<'EOF'
{
  "name": "drop",
  "time": {"dt": 5e-5, "steps": 6000},
  "effects": ["springs", "damping", "pins", "contact", "gravity"],
  "bodies": [
    {"name": "layer",
     "shape": {"type": "box", "min": [-0.03, -0.03, 0], "max": [0.03, 0.03, 0.012], "cells": [12, 12, 3]},
     "material": {"density": 1000, "youngs_modulus": 20000, "law": "exponential", "nonlinearity": 2.0, "damping": 0.002},
     "pins": [{"side": "-z"}]},
    {"name": "ball",
     "shape": {"type": "sphere", "center": [0, 0, 0.022], "radius": 0.008, "subdivisions": 2, "fill": "volume"},
     "material": {"density": 1100, "youngs_modulus": 50000, "law": "linear", "damping": 0.002}}
  ],
  "contacts": [{"host": "layer", "guest": "ball", "detector": "voxel", "eliminator": "plane", "force": 0.05}],
  "references": {"solvers": ["cgal"], "every": 50}
}
EOF
"$H" run "$T/drop.json" --out "$T/kick" 2>"$T/err"; rc=$?
[[ $rc -eq 0 ]] && grep -q "warning: contacts: contact keeps putting energy in" "$T/err" \
  && tail -1 "$T/err" | grep -q ", injects" && grep -q '"stability_verdict": "injects"' "$T/kick/summary.json" \
  && grep -q "contact keeps putting energy in" "$T/kick/summary.json" && ok || { bad "voxel drop: injection warned (exit $rc)"; cat "$T/err"; }
"$H" run "$T/drop.json" --out "$T/strict" --strict --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 && -f "$T/strict/summary.json" && -f "$T/strict/steps.csv" ]] && grep -q '"status": "error"' "$T/strict/summary.json" \
  && grep -q -- "--strict" "$T/strict/summary.json" && ok || { bad "voxel drop --strict: exit $rc, outputs written"; cat "$T/err"; }
# The same drop with exact detection and the depth penalty (conservative): no such warning.
"$H" run "$T/drop.json" --out "$T/penalty" --set 'contacts.0.detector="cgal"' --set 'contacts.0.force={"stiffness":500}' \
  --set contacts.0.two_sided=true 2>"$T/err"; rc=$?
v=$("$PY" -c "import json,sys; print(json.load(open(sys.argv[1]))['stability_verdict'])" "$T/penalty/summary.json")
[[ $rc -eq 0 && ( "$v" == steady || "$v" == settled ) ]] && ! grep -q "putting energy in" "$T/err" \
  && ok || { bad "penalty drop: verdict $v, exit $rc"; cat "$T/err"; }

# A reference whose surfaces.csv has a non-finite node: --compare refuses it naming the node.
"$H" run "$T/drop.json" --out "$T/ref" --steps 50 --quiet 2>/dev/null
cp -r "$T/ref" "$T/nanref"
"$PY" - "$T/nanref/surfaces.csv" <<'EOF'
import sys
p = sys.argv[1]
lines = open(p).read().splitlines()
f = lines[5].split(",")          # the 5th node of the first body
f[3] = "nan"                     # its y
lines[5] = ",".join(f)
open(p, "w").write("\n".join(lines) + "\n")
EOF
node=$(sed -n 6p "$T/nanref/surfaces.csv" | cut -d, -f2)
"$H" run "$T/drop.json" --out "$T/vsnan" --steps 50 --quiet --compare "$T/nanref" 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && grep -q "body \"layer\" node $node: position not finite" "$T/err" \
  && [[ ! -e "$T/vsnan/summary.json" ]] && ok || { bad "non-finite reference node: exit $rc"; cat "$T/err"; }
# A signed distance missing for one node while the others are measured: refused likewise.
cp -r "$T/ref" "$T/sdref"
"$PY" - "$T/sdref/surfaces.csv" <<'EOF'
import sys
p = sys.argv[1]
lines = open(p).read().splitlines()
f = lines[7].split(",")
f[8] = "inf"
lines[7] = ",".join(f)
open(p, "w").write("\n".join(lines) + "\n")
EOF
node=$(sed -n 8p "$T/sdref/surfaces.csv" | cut -d, -f2)
"$H" run "$T/drop.json" --out "$T/vssd" --steps 50 --quiet --compare "$T/sdref" 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q "node $node: signed distance not finite" "$T/err" && ok || { bad "non-finite signed distance: exit $rc"; cat "$T/err"; }

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
