#!/usr/bin/env bash
# A contact response built outside the tree (docs/plugins.md): the example plug-in
# (experiments/plugins/hertz) is copied to a temporary folder and built there with
# find_package(harness) against this build; a scene beside it names it ("plugin:PATH", relative
# to the scene file). With exponent 1 it is the built-in linear penalty: after 3000 steps of the
# spheres (in contact both ways from about step 1900) its surfaces lie within 1e-12 m of the
# built-in's (measured 3.7e-17 m, summation order only: a margin of 27,000), and one 1 % stiffer
# lies far outside (measured 4.7e-6 m; asserted > 1e-9). summary.json names it (pairs[].response,
# "plugin:hertz"), and the scene's `force` does not change its run. Bad plug-ins and parameters are one-line errors with exit 2 naming the key:
# a missing file, a file that is not a shared library, a missing symbol, another interface
# version, parameters the plug-in refuses, a parameter that is not a number, parameters without a
# response, a response that is not "plugin:...", the implicit integrator, projection, --device.
# A plug-in that fails a step fails the run there (exit 3, as any failed step: summary status
# "error" naming the plug-in and its message).
# Usage: test_plugin.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
BUILD="$(cd "$(dirname "$H")/.." && pwd)"
[ -f "$BUILD/harnessConfig.cmake" ] || { echo "FAIL: no $BUILD/harnessConfig.cmake"; exit 1; }
command -v cc >/dev/null || { echo "FAIL: no C compiler"; exit 1; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# Out of the tree: copy the example, configure and build it against the build folder.
cp -r "$SRC/experiments/plugins/hertz" "$T/hertz"
cmake -S "$T/hertz" -B "$T/hertz/build" -Dharness_DIR="$BUILD" >"$T/cmake.log" 2>&1 &&
  cmake --build "$T/hertz/build" >>"$T/cmake.log" 2>&1 || { cat "$T/cmake.log"; echo "FAIL: the example plug-in does not build"; exit 1; }
[ -f "$T/hertz/build/libhertz.so" ] || { echo "FAIL: no libhertz.so"; exit 1; }

# Broken plug-ins, built straight with cc against the header: another interface version, a
# missing symbol, one that fails its steps.
cat >"$T/broken.c" <<'EOF'
#include <harness/response.h>
#include <stdio.h>
HARNESS_RESPONSE_EXPORT int harness_response_abi(void) { return ABI; }
HARNESS_RESPONSE_EXPORT const char* harness_response_name(void) { return "broken"; }
HARNESS_RESPONSE_EXPORT void* harness_response_create(int n, const char* const* k, const double* v, char* e, int s) {
  (void)n, (void)k, (void)v, (void)e, (void)s;
  static int state;
  return &state;
}
#ifndef NO_FORCES
HARNESS_RESPONSE_EXPORT int harness_response_forces(void* st, const harness_contacts* c, const harness_body* g,
                                                    const harness_body* h, double* fg, double* fh, char* e, int s) {
  (void)st, (void)g, (void)h, (void)fg, (void)fh;
  if (c->count == 0) return 0;
  snprintf(e, (size_t)s, "cannot handle %d contacts", c->count);
  return 7;
}
#endif
HARNESS_RESPONSE_EXPORT void harness_response_destroy(void* st) { (void)st; }
EOF
for v in "abi99 -DABI=99" "nosym -DABI=HARNESS_RESPONSE_ABI -DNO_FORCES" "fails -DABI=HARNESS_RESPONSE_ABI"; do
  set -- $v
  name=$1; shift
  cc -shared -fPIC -I"$SRC/core/plugin" "$@" -o "$T/lib$name.so" "$T/broken.c" || bad "cc $name"
done
echo "not a library" >"$T/libtext.so"

# The scenes: the spheres small (2 subdivisions), voxel_exact with the plane, both ways, no
# references; the built-in penalty k = 500 N/m, the plug-in at k and at 1.01 k.
"$PY" - "$SRC" "$T" <<'PYEOF' || { echo "FAIL: writing the scenes"; exit 1; }
import json, sys
src, T = sys.argv[1:]
s = json.load(open(src + "/experiments/scenes/sphere_collision.json"))
for b in s["bodies"]:
    b["shape"]["subdivisions"] = 2
c = s["contacts"][0]
c.update({"detector": "voxel_exact", "eliminator": "plane", "force": {"stiffness": 500}, "two_sided": True})
s["references"] = {"solvers": []}
s.setdefault("output", {})["frames_every"] = 0
json.dump(s, open(T + "/builtin.json", "w"), indent=1)
c["response"] = "plugin:hertz/build/libhertz.so"
for name, params in (("plugin", {"stiffness": 500}), ("stiffer", {"stiffness": 505})):
    c["response_parameters"] = params
    json.dump(s, open("%s/%s.json" % (T, name), "w"), indent=1)
# The scene's force rule is not used with a response: the automatic force's scene gives the
# plug-in the same pushes (contact normals and depths) as the penalty's.
c["response_parameters"], c["force"] = {"stiffness": 500}, "auto"
json.dump(s, open(T + "/plugin_auto.json", "w"), indent=1)
PYEOF

"$H" run "$T/builtin.json" --steps 3000 --quiet --out "$T/b" || bad "built-in run exited $?"
"$H" run "$T/plugin.json" --steps 3000 --quiet --out "$T/p" --compare "$T/b" || bad "plug-in run exited $?"
"$H" run "$T/stiffer.json" --steps 3000 --quiet --out "$T/s" --compare "$T/b" || bad "stiffer plug-in run exited $?"
"$H" run "$T/plugin_auto.json" --steps 3000 --quiet --out "$T/a" --compare "$T/b" || bad "plug-in run (force auto) exited $?"
"$PY" - "$T" <<'PYEOF' || bad "the plug-in is not the built-in penalty"
import csv, json, sys
T = sys.argv[1]
s = {k: json.load(open("%s/%s/summary.json" % (T, k))) for k in "bpsa"}
assert s["a"]["state_hash"] == s["p"]["state_hash"], "the scene's force rule changed a plug-in's run"
assert s["b"]["pairs"][0]["response"] is None, s["b"]["pairs"][0]["response"]
for k in "ps":
    assert s[k]["status"] == "ok" and s[k]["pairs"][0]["response"] == "plugin:hertz", (k, s[k]["pairs"][0]["response"])
    assert s[k]["resolved_scene"]["contacts"][0]["response"] == "plugin:hertz/build/libhertz.so"
contact_steps = sum(1 for r in csv.DictReader(open(T + "/b/steps.csv")) if float(r["contacts"]) > 0)
assert contact_steps >= 800, contact_steps
same, stiffer = (s[k]["pairs"][0]["error_vs_reference"]["pos_err_max"] for k in "ps")
print("plug-in vs built-in: %.3g m over %d steps in contact; 1%% stiffer: %.3g m" % (same, contact_steps, stiffer))
assert same < 1e-12, same
assert stiffer > 1e-9, stiffer
PYEOF

# Bad input: one line on stderr naming the key, exit 2, nothing left looking complete.
expect2() {  # expect2 WHAT KEY-REGEX -- harness arguments
  local what="$1" key="$2"; shift 3
  "$H" run "$@" --steps 5 --quiet --out "$T/bad" 2>"$T/err"; local rc=$?
  if [[ $rc -ne 2 ]] || ! grep -Eq "$key" "$T/err" || [[ $(wc -l <"$T/err") -ne 1 ]] || [ -f "$T/bad/summary.json" ]; then
    bad "$what: exit $rc: $(cat "$T/err")"
  fi
  rm -rf "$T/bad"
}
P="$T/plugin.json"
expect2 "missing file" 'contacts\.0\.response: no plug-in file .*nope\.so' -- "$P" --set 'contacts.0.response="plugin:nope.so"'
expect2 "not a library" 'contacts\.0\.response: cannot load' -- "$P" --set 'contacts.0.response="plugin:libtext.so"'
expect2 "missing symbol" 'contacts\.0\.response: .*no symbol harness_response_forces' -- "$P" --set 'contacts.0.response="plugin:libnosym.so"'
expect2 "another version" 'contacts\.0\.response: .*version 99.*version 1' -- "$P" --set 'contacts.0.response="plugin:libabi99.so"'
expect2 "refused parameters" 'contacts\.0\.response_parameters: plugin:hertz refused them: unknown parameter "k"' -- "$P" --set 'contacts.0.response_parameters={"k": 1}'
expect2 "a parameter not a number" 'contacts\.0\.response_parameters\.stiffness' -- "$P" --set 'contacts.0.response_parameters={"stiffness": "soft"}'
expect2 "parameters without a response" 'contacts\.0\.response_parameters: only with response' -- "$T/builtin.json" --set 'contacts.0.response_parameters={"stiffness": 1}'
expect2 "not plugin:" 'contacts\.0\.response: expected "plugin:PATH"' -- "$P" --set 'contacts.0.response="hertz"'
expect2 "implicit" 'time\.integrator: .*stiffness' -- "$P" --set 'time.integrator="implicit_euler"'
expect2 "projection" 'contacts\.0\.eliminator: .*projection' -- "$P" --set 'contacts.0.eliminator="projection"'
expect2 "--device" 'contacts\.0\.response: a response of its own \(plugin:hertz\)' -- "$P" --set 'contacts.0.detector="voxel"' --set 'contacts.0.eliminator="line"' --device cuda

# A plug-in that fails a step: the run fails at that step, says why, exit 3.
"$H" run "$P" --set 'contacts.0.response="plugin:libfails.so"' --steps 3000 --quiet --out "$T/f" 2>"$T/err"; rc=$?
"$PY" - "$T/f" "$rc" <<'PYEOF' || bad "a failing plug-in: exit $rc $(cat "$T/err")"
import json, sys
d, rc = sys.argv[1], int(sys.argv[2])
s = json.load(open(d + "/summary.json"))
assert rc == 3, rc
assert s["status"] == "error" and "plugin:broken" in s["error"] and "cannot handle" in s["error"], (s["status"], s["error"])
PYEOF

[[ $fails -eq 0 ]] && echo "plugin: all passed" || exit 1
