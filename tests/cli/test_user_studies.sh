#!/usr/bin/env bash
# A scene of the user's through every study that takes one (scripts/study.py all --scene FILE --out
# DIR: accuracy, ablation, convergence, refinement, realtime, swap, detection, restriction, regime) and its card: the tutorial's scene (docs/tutorial.md), --quick runs, its
# reference made by the study; every output in DIR, nothing written into the repository's results/.
# Usage: test_user_studies.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
PY="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
# The tutorial's scene, as the tutorial writes it.
"$PY" - "$SRC/docs/tutorial.md" "$T/my_press.json" <<'PY' || { echo "FAIL: no scene in the tutorial"; exit 1; }
import re, sys
body = re.search(r"```json file=my_press.json\n(.*?)```", open(sys.argv[1]).read(), re.S).group(1)
open(sys.argv[2], "w").write(body)
PY
before=$(find "$SRC/results" -type f -newer "$T/my_press.json" | wc -l)
cd "$T"
"$PY" "$SRC/scripts/study.py" all --harness "$H" --scene my_press.json --out st --quick -j 2 --repeats 1 \
  > log 2>&1 || { bad "study.py all --scene"; tail -20 log; }
for f in st/accuracy_time.csv st/ablation.csv st/defaults.json st/tables/accuracy_time.md st/tables/ablation.md \
         st/figures/pareto_my_press.png st/figures/ablation_my_press.png st/references/my_press/summary.json \
         st/convergence.csv st/refinement.csv st/realtime.csv st/swap.csv st/tables/realtime.md st/tables/swap.md \
         st/restriction.csv st/tables/restriction.md st/regime.csv st/tables/regime.md; do
  [[ -s "$f" ]] || bad "no $f"
done
"$PY" - st <<'PY' || bad "the studies' rows"
import csv, json, sys
acc = list(csv.DictReader(open(sys.argv[1] + "/accuracy_time.csv")))
abl = list(csv.DictReader(open(sys.argv[1] + "/ablation.csv")))
assert acc and abl and {r["scene"] for r in acc} == {"my_press"} == {r["scene"] for r in abl}
# the footing voxels from the tissue's node spacing (5 mm edges: 7.8125 and 15.625 mm)
assert {r["voxel_mm"] for r in acc if r["detector"] == "voxel"} == {"7.8125", "15.625"}, acc[0]
assert "no contact force" in {r["config"] for r in acc}
# the run's C++ class, and stable exactly when it is settled or steady
classes = ("settled", "steady", "chatters", "injects", "grows", "forced", "failed")
assert all(r["stability"] in classes and r["stability_class"] for r in acc + abl), [r["stability"] for r in acc + abl]
assert all((r["stable"] == "yes") == (r["stability"] in ("settled", "steady")) for r in acc + abl)
assert list(json.load(open(sys.argv[1] + "/defaults.json"))) == ["my_press"]
for name in ["convergence", "refinement", "realtime", "swap", "restriction", "regime"]:
    rows = list(csv.DictReader(open("%s/%s.csv" % (sys.argv[1], name))))
    assert rows and {r["scene"] for r in rows} == {"my_press"}, name
# useless beside stable, and a front of the evidence only (no stable run that tunnels or does not help)
assert all(r["useless"] == "baseline" for r in acc if r["config"] == "no contact force")
assert all(r["stable"] == "yes" and r["useless"] == "" for r in acc if r["front"] == "yes"), acc
assert all("useless" in r and "helps" in r for r in abl)
rt = list(csv.DictReader(open(sys.argv[1] + "/realtime.csv")))
assert {r["method"] for r in rt if r["kind"] == "exact"} == {"cgal both ways, penalty"}  # set in full, not the scene's own
swap = list(csv.DictReader(open(sys.argv[1] + "/swap.csv")))
assert {(r["host"], r["swapped"]) for r in swap} == {("tissue", "no"), ("probe", "yes")}
PY
"$PY" "$SRC/scripts/study.py" card --harness "$H" --scene my_press.json --reference st/references/my_press --out card \
  --set time.settle=null >> log 2>&1 && grep -q "^| no contact force |" card/card.md || bad "the card"
# The scorecard: a method of the user's (a stiffer penalty with the exact narrow phase) judged
# beside the built-in detectors, its standing per scene in scorecard.md and scorecard.csv.
"$PY" "$SRC/scripts/study.py" scorecard --harness "$H" --scenes my_press.json --reference st/references/my_press \
  --out sc --set time.settle=null --method 'k200=contacts.0.force={"stiffness":200},contacts.0.detector="voxel_exact"' \
  >> log 2>&1 || bad "the scorecard"
"$PY" - sc <<'PY' || bad "the scorecard's rows"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/scorecard.csv")))
mine = [r for r in rows if r["method"] == "k200"]
assert len(mine) == 1 and mine[0]["builtin"] == "no", rows
assert mine[0]["standing"] in ("closer", "farther", "cannot tell", "fails", "no built-in passes"), mine[0]
assert {r["method"] for r in rows if r["builtin"] == "yes"} == {"voxel", "voxel_exact", "cgal"}
if mine[0]["standing"] in ("closer", "farther", "cannot tell"):
    assert float(mine[0]["error_ratio_lo"]) <= float(mine[0]["error_ratio"]) <= float(mine[0]["error_ratio_hi"]), mine[0]
assert "**k200**" in open(sys.argv[1] + "/scorecard.md").read()
PY
after=$(find "$SRC/results" -type f -newer "$T/my_press.json" | wc -l)
[[ $after -eq $before ]] || bad "files written into results/: $((after - before))"
"$PY" "$SRC/scripts/study.py" region --scene my_press.json --out x > err 2>&1; rc=$?
[[ $rc -eq 2 ]] && grep -q "bundled scenes only" err || bad "a study without --scene support is refused: exit $rc"
[[ $fail -eq 0 ]] && echo "user scene: six studies and the card in $(du -sh st | cut -f1)"
exit $fail
