#!/usr/bin/env bash
# `harness bench` on a tiny size: the CSV has the columns docs/usage.md names and one row per method and
# thread count (fcl and cgal when the build has the references). Times are not checked.
# Also `harness run --threads`: results do not depend on the thread count.
# Usage: test_bench.sh HARNESS SOURCE_DIR
set -u
H="$1"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0; pass=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL: $*"; fail=$((fail+1)); }

"$H" bench --quick --sizes 1000 --min-time 0 --out "$T/bench.csv" 2>"$T/err" && ok || { bad "bench ran"; cat "$T/err"; }
head -1 "$T/bench.csv" | grep -q '^method,nodes,threads,us_per_step,bytes' && ok || bad "bench columns"
for m in voxel_detect voxel_detect_eliminate voxel_exact_detect voxel_exact_detect_eliminate stream_positions step step_audited stream_step arith_floor pass_floor; do
  for t in 1 2; do
    grep -q "^$m,1000,$t,[0-9.]*,[0-9]*," "$T/bench.csv" && ok || bad "row $m threads $t"
  done
done
for m in hash_detect hash_detect_cell_x0.5 hash_detect_cell_x2 hash_detect_cell_x4; do
  grep -q "^$m,1000,1,[0-9.]*,[0-9]*,.*single-threaded" "$T/bench.csv" && ok || bad "row $m"
done
if "$H" --help 2>/dev/null | grep -q bench && grep -q "^fcl,1000,1," "$T/bench.csv"; then
  grep -q "^cgal,1000,1," "$T/bench.csv" && ok || bad "cgal row"
fi
# the node order rows (one thread): timed side by side with the step row's layout, the ratio in the note
for m in step_order_rcm step_order_morton step_shuffled_order_scene step_shuffled_order_rcm step_shuffled_order_morton; do
  grep -q "^$m,1000,1,[0-9.]*,[0-9]*,.*x the step row's layout side by side" "$T/bench.csv" && ok || bad "row $m"
done
# the step with the bundled scenes' law and effects (one thread): timed side by side with the step row
grep -q "^step_scene_laws,1000,1,[0-9.]*,[0-9]*,.*exponential.*x the step row side by side" "$T/bench.csv" && ok \
  || bad "row step_scene_laws"
# step rows carry their ns per spring and their ratio to stream_step of the same run
head -1 "$T/bench.csv" | grep -q ',ns_per_spring,step_over_stream,device,machine$' && ok \
  || bad "bench ns_per_spring, step_over_stream, device, machine columns"
awk -F, 'NR > 1 && $15 != "cpu" {exit 1}' "$T/bench.csv" && ok || bad "CPU rows name their device cpu"
# --device cuda: on a machine without a GPU (or a build without CUDA), exit 2 with one line
if ! command -v nvidia-smi >/dev/null || ! nvidia-smi -L >/dev/null 2>&1; then
  "$H" bench --device cuda --sizes 1000 --out "$T/g.csv" 2>"$T/err"; rc=$?
  [[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && grep -q -- "--device" "$T/err" && ok || bad "bench --device cuda without a GPU: exit $rc"
fi
awk -F, '($1=="step" || $1=="step_audited") && !($13 > 0 && $14 > 0) {exit 1}' "$T/bench.csv" && ok || bad "step rows: ns per spring and stream ratio"
# voxel rows carry the grid's bytes (> 0); voxel_exact rows name their band count
awk -F, '$1=="voxel_detect" && $5 <= 0 {exit 1}' "$T/bench.csv" && ok || bad "voxel bytes > 0"
grep -q "^voxel_exact_detect,1000,1,.*beyond the band" "$T/bench.csv" && ok || bad "voxel_exact note"
# bad input: exit 2, one line
"$H" bench --out "$T/x.csv" --sizes 0 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && ok || bad "bad --sizes: exit $rc"
"$H" bench --out "$T/x.csv" --methods voxel_detect,nope 2>"$T/err"; rc=$?
[[ $rc -eq 2 && $(wc -l < "$T/err") -eq 1 ]] && grep -q "nope" "$T/err" && ok || bad "bad --methods: exit $rc"
# --methods keeps only the rows asked for
"$H" bench --sizes 1000 --threads 1 --min-time 0 --methods stream_positions,voxel_detect --out "$T/m.csv" 2>/dev/null \
  && ok || bad "bench --methods ran"
[[ $(tail -n +2 "$T/m.csv" | cut -d, -f1 | sort | tr '\n' ' ') == "stream_positions voxel_detect " ]] && ok \
  || bad "--methods rows: $(tail -n +2 "$T/m.csv" | cut -d, -f1 | tr '\n' ' ')"

# `harness run --threads N`: the same state hash with 1 and 2 threads; a bad count is bad input.
for t in 1 2; do
  "$H" run cylinder_press --steps 30 --threads $t --set 'references.solvers=[]' --out "$T/run$t" --quiet 2>"$T/err" \
    && ok || { bad "run --threads $t"; cat "$T/err"; }
done
h1=$(grep -o '"state_hash": *"[0-9a-f]*"' "$T/run1/summary.json")
h2=$(grep -o '"state_hash": *"[0-9a-f]*"' "$T/run2/summary.json")
[[ -n "$h1" && "$h1" == "$h2" ]] && ok || bad "state hash differs between 1 and 2 threads: $h1 / $h2"
"$H" run cylinder_press --steps 1 --threads 0 --out "$T/run0" --quiet 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && ok || bad "--threads 0: exit $rc"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
