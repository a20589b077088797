#!/usr/bin/env bash
# What a run writes against docs/outputs.md's tables (core/run/outputs_doc.cpp), and the record's
# rule: a rerun that reproduces the state changes timing.csv and summary.json's keys marked
# "varies" only.
#  (a) steps.csv's header is the page's steps.csv table, timing.csv's its timing table, row for row;
#  (b) every key a run writes into summary.json (top level, pairs[], timing_us), with --compare and
#      --compare-also, is described on the page;
#  (c) the same run twice: steps.csv byte for byte, summary.json equal once the "varies" keys are
#      taken out, and the state hash equal.
# Usage: test_outputs.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"; PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
REF="$SRC/results/references/sphere_collision"
ALSO="$SRC/results/references/sphere_collision_one_sided"
for k in a b; do
  HARNESS_THREADS=1 "$H" run sphere_collision --out "$T/$k" --steps 40 --quiet --compare "$REF" --compare-also "$ALSO" \
    --set references.every=10 2>"$T/err_$k" || { echo "FAIL: run $k: $(head -1 "$T/err_$k")"; exit 1; }
done
"$PY" - "$T" "$SRC/docs/outputs.md" <<'PYEOF'
import csv, json, re, sys
T, page = sys.argv[1], sys.argv[2]
passed = failed = 0
def check(ok, what):
    global passed, failed
    passed += ok
    failed += not ok
    if not ok:
        print("FAIL: " + what)

text = open(page).read()
def table(heading):
    part = text.split("\n## " + heading + "\n", 1)[1].split("\n## ", 1)[0]
    return [m.group(1) for m in re.finditer(r"^\| `([^`]+)` \|", part, re.M)]

steps_cols, timing_cols, keys = table("steps.csv"), table("timing.csv"), set(table("summary.json"))
rows = {k: list(csv.reader(open("%s/%s/steps.csv" % (T, k)))) for k in "ab"}
timing = list(csv.reader(open("%s/a/timing.csv" % T)))
check(rows["a"][0] == steps_cols, "steps.csv header %s is not docs/outputs.md's %s" % (rows["a"][0], steps_cols))
check(timing[0] == ["step", "pair"] + timing_cols, "timing.csv header %s" % timing[0])
check(len(timing) == len(rows["a"]) == 41, "rows: steps %d, timing %d" % (len(rows["a"]), len(timing)))
check(all(t[:2] == [r[0], r[2]] for t, r in zip(timing[1:], rows["a"][1:])), "timing.csv keyed by step and pair")

s = {k: json.load(open("%s/%s/summary.json" % (T, k))) for k in "ab"}
undoc = [k for k in s["a"] if k not in keys]
undoc += ["pairs[]." + k for p in s["a"]["pairs"] for k in p if "pairs[]." + k not in keys]
undoc += ["timing_us." + k for k in s["a"]["timing_us"] if "timing_us." + k not in keys]
check(not undoc, "summary.json keys not on docs/outputs.md: %s" % undoc)

# (c) the rerun
check(rows["a"] == rows["b"], "steps.csv differs between two runs of the same scene")
varies = [m.group(1) for m in re.finditer(r"^\| `([^`]+)` \|[^|]*\| yes \|$", text, re.M)]
def strip(d):
    d = json.loads(json.dumps(d))
    for k in varies:
        if k.startswith("timing_us."):
            d.get("timing_us", {}).pop(k.split(".", 1)[1], None)
        elif "." not in k and "[]" not in k:
            d.pop(k, None)
    return d
check(s["a"]["state_hash"] == s["b"]["state_hash"], "state hashes differ")
a, b = strip(s["a"]), strip(s["b"])
diff = [k for k in set(a) | set(b) if a.get(k) != b.get(k)]
check(not diff, "summary.json differs outside the keys that vary: %s" % diff)
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
PYEOF
