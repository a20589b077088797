#!/usr/bin/env bash
# The GPU part of the harness, in one call on a machine with a CUDA GPU (an H100 or H200) that has
# nvcc, CMake and ninja but no Debian packages and no network: builds `harness` with the CUDA
# backend (reference solvers off), runs each bundled scene on the GPU with the CPU's step beside it
# (--check-cpu: the largest node distance after the steps), and the device bench (10^3 to 10^7
# nodes per body). Header-only dependencies (Eigen, nlohmann-json, CLI11) travel as Debian
# packages in .devdeps/ (scripts/device_check.sh --fetch, here, before the call).
# Usage: scripts/device_check.sh --fetch        (on the CPU machine: download the packages)
#        OUT=DIR scripts/device_check.sh        (on the GPU machine)
set -uo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--fetch" ]]; then
  mkdir -p .devdeps && cd .devdeps && apt-get download libeigen3-dev nlohmann-json3-dev libcli11-dev
  exit $?
fi
OUT="${OUT:-out/device}"
# Only the standard library's json is needed here: any python3 will do where Debian's is missing.
PYTHON="${PYTHON:-/usr/bin/python3}"
[[ -x "$PYTHON" ]] || PYTHON=python3
STEPS="${STEPS:-1000}"
mkdir -p "$OUT/runs"
log="$OUT/device.log"
exec > >(tee "$log") 2>&1
nvidia-smi -L || true
for f in .devdeps/*.deb; do dpkg -x "$f" /; done
t0=$(date +%s)
cmake -S . -B build-cuda -G Ninja -DCMAKE_BUILD_TYPE=Release -DHARNESS_BUILD_REFERENCE=OFF -DHARNESS_BUILD_TESTS=OFF \
  -DHARNESS_CUDA=on -DCMAKE_CUDA_ARCHITECTURES=90 >/dev/null || exit 1
cmake --build build-cuda -j 16 --target harness || exit 1
echo "build: $(( $(date +%s) - t0 )) s"
H=build-cuda/bin/harness
# 10^7 nodes per body: its world takes minutes to build on one CPU core, so it starts now, beside
# the rest (whose GPU work ends long before that world is built).
"$H" bench --device cuda --sizes 10000000 --min-time 0.5 --out "$OUT/bench_cuda_1e7.csv" > "$OUT/bench_1e7.log" 2>&1 &
big=$!
run() {  # name scene args...
  local name=$1 scene=$2; shift 2
  timeout 120 "$H" run "$scene" --device cuda --check-cpu --steps "$STEPS" --quiet --out "$OUT/runs/$name" "$@" \
    || echo "run $name: exit $?"
}
for s in sphere_collision cylinder_press implant_expansion; do
  run "${s}_voxel_exact" "$s" --set 'contacts.0.detector="voxel_exact"' --set 'references.solvers=[]'
  run "${s}_voxel_line" "$s" --set 'contacts.0.detector="voxel"' --set 'contacts.0.force=0.001' \
    --set 'contacts.0.two_sided=false' --set 'references.solvers=[]'
done
# The completed model over the whole of time.steps (no settling), for the real-time factor.
for s in sphere_collision cylinder_press implant_expansion; do
  n=$("$PYTHON" -c "import json,sys; print(json.load(open('experiments/scenes/$s.json'))['time']['steps'])")
  timeout 120 "$H" run "$s" --device cuda --check-cpu --quiet --steps "$n" --out "$OUT/runs/${s}_voxel_exact_full" \
    --set 'contacts.0.detector="voxel_exact"' --set 'references.solvers=[]' || echo "full $s: exit $?"
done
tar czf "$OUT/runs.tgz" -C "$OUT" runs && rm -rf "$OUT/runs"
timeout 150 "$H" bench --device cuda --sizes 1000,10000,100000,1000000 --min-time 0.5 --out "$OUT/bench_cuda.csv" \
  || echo "bench: exit $?"
left=$(( ${BUDGET_S:-600} - ($(date +%s) - t0) ))
( sleep "$(( left > 0 ? left : 1 ))"; kill $big 2>/dev/null ) &
wait $big || echo "bench 1e7: exit $?"
cat "$OUT/bench_1e7.log"
# PROFILE=1: per kernel, what 20 steps of each scene's completed model cost (Nsight Compute's
# gpu__time_duration per kernel launch, the graph's nodes profiled one by one; one CSV per scene):
# the profile the next optimisation starts from.
if [[ "${PROFILE:-0}" == 1 ]] && command -v ncu >/dev/null; then
  for s in sphere_collision cylinder_press implant_expansion; do
    timeout 120 ncu --csv --metrics gpu__time_duration.sum \
      "$H" run "$s" --device cuda --quiet --steps 20 --out "$OUT/prof_$s" --set 'contacts.0.detector="voxel_exact"' \
      --set 'references.solvers=[]' > "$OUT/ncu_$s.csv" 2>&1 || echo "ncu $s: exit $?"
  done
fi
echo "total: $(( $(date +%s) - t0 )) s"
for f in "$OUT"/bench_cuda*.csv; do echo "== $f"; cut -d, -f1-5,14 "$f"; done
