#!/usr/bin/env bash
# Fuzzes the scene loader and the OFF / OBJ readers with libFuzzer (clang, ASan + UBSan).
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
#   SECONDS  run time of each target (default 60); targets run one after another
#   TARGET   scene, off, obj (default all three)
# Installs clang if missing, configures build-fuzz/ (CMake option HARNESS_FUZZ=ON, clang, and
# HARNESS_CUDA=off: the fuzzing flags would reach nvcc's host compiler where a CUDA toolkit is installed),
# builds fuzz_scene, fuzz_off, fuzz_obj (JOBS build jobs, default 2) and runs each on a copy of
# its seed corpus tests/fuzz/corpus/<target>/ with the dictionary tests/fuzz/<target>.dict: the
# committed corpus is never changed. After the
# run the inputs that add coverage beyond the seeds are merged into
# build-fuzz/fuzz-out/<target>/new/ (copy the ones worth keeping into the corpus by hand);
# crashes, leaks and timeouts are written to build-fuzz/fuzz-out/<target>/ as crash-*, leak-*,
# timeout-*, oom-* and slow-unit-*. Replay one with: build-fuzz/bin/fuzz_<target> FILE.
# Exit status: 0 when no target crashed, 1 otherwise (2: bad usage or build failure).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2; }
shift || true
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(scene off obj)
for t in "${targets[@]}"; do
  case "$t" in scene | off | obj) ;; *) echo "fuzz.sh: unknown target '$t' (scene, off, obj)" >&2; exit 2 ;; esac
done

# Longest input per target: the bundled scenes are about 1.3 kB, the seed meshes a few hundred
# bytes; the fuzz targets bound the size of what they build (tests/fuzz/fuzz_scene.cpp).
declare -A max_len=([scene]=4096 [off]=4096 [obj]=4096)

# clang and its runtime (libFuzzer, sanitizers), from Debian.
pkgs=()
command -v clang++ >/dev/null || pkgs+=(clang)
ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 ||
  pkgs+=(libclang-rt-14-dev)
if [[ ${#pkgs[@]} -gt 0 ]]; then
  echo "fuzz.sh: installing ${pkgs[*]}"
  SUDO=""
  [[ $(id -u) -eq 0 ]] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${pkgs[@]}"
fi
scripts/install-deps.sh >/dev/null

dir=build-fuzz
if [[ ! -f "$dir/CMakeCache.txt" ]]; then
  gen=()
  command -v ninja >/dev/null && gen=(-G Ninja)
  CC=clang CXX=clang++ cmake -S . -B "$dir" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DHARNESS_FUZZ=ON -DHARNESS_BUILD_TESTS=OFF -DHARNESS_BUILD_REFERENCE=OFF -DHARNESS_CUDA=off
fi
bins=()
for t in "${targets[@]}"; do bins+=("fuzz_$t"); done
cmake --build "$dir" -j "${JOBS:-2}" --target "${bins[@]}" || exit 2

out="$dir/fuzz-out"
mkdir -p "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
failed=()
summary=()
for t in "${targets[@]}"; do
  bin="$dir/bin/fuzz_$t"
  seeds="tests/fuzz/corpus/$t"
  tdir="$out/$t"
  rm -rf "$tdir"
  mkdir -p "$tdir/corpus" "$tdir/new"
  cp "$seeds"/* "$tdir/corpus/"
  echo "== fuzz_$t: $seconds s, max_len ${max_len[$t]}, $(ls "$seeds" | wc -l) seeds"
  status=0
  "$bin" -max_total_time="$seconds" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 \
    -dict="tests/fuzz/$t.dict" -print_final_stats=1 -artifact_prefix="$tdir/" "$tdir/corpus" \
    2>"$tdir/log.txt" || status=$?
  tail -n 25 "$tdir/log.txt"
  # Coverage and speed: the last status line and the final statistics.
  last=$(grep -E '^#[0-9]+' "$tdir/log.txt" | tail -n 1 || true)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$tdir/log.txt" | tail -n 1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$tdir/log.txt" | tail -n 1)
  rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$tdir/log.txt" | tail -n 1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
  # Inputs that add coverage beyond the seeds, minimised.
  cp "$seeds"/* "$tdir/new/"
  "$bin" -merge=1 -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 "$tdir/new" "$tdir/corpus" \
    >"$tdir/merge.txt" 2>&1 || true
  for f in "$seeds"/*; do rm -f "$tdir/new/$(basename "$f")"; done
  n_new=$(ls "$tdir/new" | wc -l)
  line="fuzz_$t: status $status, ${execs:-?} execs, ${rate:-?} execs/s, cov ${cov:-?}, ft ${ft:-?}, corpus ${corp:-?}, peak rss ${rss:-?} MB, $n_new new inputs in $tdir/new"
  summary+=("$line")
  echo "$line"
  if [[ $status -ne 0 ]]; then
    failed+=("$t")
    ls "$tdir" | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | sed "s|^|  artifact: $tdir/|" || true
  fi
done
printf '%s\n' "${summary[@]}" >"$out/summary.txt"
echo "== summary ($out/summary.txt)"
printf '%s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz.sh: crashes in: ${failed[*]}" >&2
  exit 1
fi
