#!/usr/bin/env bash
# `harness run --ensemble K` (core/run/ensemble.cpp): K members differing only in what a user
# cannot control (node order, an initial jitter far below the mesh's precision). Checks: the
# members' folders and their node orders and seeds; the classes counted over the members; the
# ensemble's class is the shared one or "flips"; each figure's range holds every member's value and
# its median lies within it; the jitter changes the state (members' hashes differ) but not the
# outcome beyond the figures' ranges; the same ensemble run twice gives the same summary figures;
# a bad K is exit 2 naming --ensemble.
# Usage: test_ensemble.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fails=0
for k in a b; do
  HARNESS_THREADS=1 "$H" run sphere_collision --steps 400 --quiet --ensemble 3 --out "$T/$k" \
    --set 'references.every=100' 2>"$T/err_$k" || { echo "FAIL: ensemble run $k: $(head -1 "$T/err_$k")"; fails=1; }
done
"$H" run sphere_collision --steps 5 --quiet --ensemble 0 --out "$T/bad" 2>"$T/err_bad"; rc=$?
[[ $rc -eq 2 ]] && grep -q -- "--ensemble" "$T/err_bad" || { echo "FAIL: --ensemble 0: exit $rc $(cat "$T/err_bad")"; fails=1; }
"$PY" - "$T" <<'PYEOF' || fails=1
import json, os, sys
T = sys.argv[1]
passed = failed = 0
def check(ok, what):
    global passed, failed
    passed += ok
    failed += not ok
    if not ok:
        print("FAIL: " + what)

s = json.load(open(os.path.join(T, "a", "summary.json")))
e = s.get("ensemble", {})
check(e.get("members") == 3, "members: %s" % e.get("members"))
runs = e.get("member_runs", [])
check([r["node_order"] for r in runs] == ["scene", "rcm", "morton"], "node orders %s" % [r.get("node_order") for r in runs])
check([r["jitter_seed"] for r in runs] == [None, 1, 2], "seeds %s" % [r.get("jitter_seed") for r in runs])
members = [s] + [json.load(open(os.path.join(T, "a", r["dir"], "summary.json"))) for r in runs[1:]]
classes = {}
for m in members:
    classes[m["stability_verdict"]] = classes.get(m["stability_verdict"], 0) + 1
check(e.get("classes") == classes, "classes %s, members say %s" % (e.get("classes"), classes))
shared = next(iter(classes)) if len(classes) == 1 else "flips"
check(s["stability_verdict"] == shared == e.get("stability_verdict"), "class %s, expected %s" % (s["stability_verdict"], shared))
check(len({m["state_hash"] for m in members}) == 3, "the jitter and the order change the state: hashes %s" % [m["state_hash"] for m in members])
# every figure's range holds its members' values
def at(d, ptr):
    for p in ptr.strip("/").split("/"):
        d = d[int(p)] if isinstance(d, list) else d[p]
    return d
figs = e.get("figures", {})
check("/pairs/0/max_depth_peak" in figs and "/window/chatter_amplitude_m" in figs, "figures: %s" % sorted(figs)[:5])
for ptr, f in figs.items():
    vals = []
    for m in members:
        try:
            v = at(m, ptr)
        except (KeyError, IndexError, TypeError):
            continue
        if isinstance(v, bool):
            v = float(v)
        if isinstance(v, (int, float)):
            vals.append(v)
    ok = f["min"] <= f["median"] <= f["max"] and all(f["min"] <= v <= f["max"] for v in vals) and len(vals) == f["members"]
    check(ok, "%s: %s against members %s" % (ptr, f, vals))
b = json.load(open(os.path.join(T, "b", "summary.json")))["ensemble"]
check(b["figures"] == e["figures"] and b["classes"] == e["classes"], "a second run of the ensemble differs")
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
PYEOF
exit $fails
