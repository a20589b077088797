#!/usr/bin/env bash
# HARNESS_ISA (core/cpu.hpp): a level the processor runs is taken, an unknown word or a level it
# cannot run is rejected at start-up with one line on stderr and exit status 2, before anything
# is written. (Every level's results: tests/cli/test_golden.sh and tests/core/test_cpu.cpp.)
# Usage: test_isa.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0; pass=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL: $*"; fail=$((fail+1)); }

# rejected WORD EXPECTED: `harness run` exits 2 with exactly the line EXPECTED, writing nothing.
rejected() {
  HARNESS_ISA="$1" "$H" run cylinder_press --out "$T/rejected" --steps 5 --quiet >"$T/out" 2>"$T/err"
  local rc=$?
  [[ $rc -eq 2 ]] && ok || bad "HARNESS_ISA='$1': exit $rc, expected 2"
  [[ $(wc -l < "$T/err") -eq 1 ]] && ok || { bad "HARNESS_ISA='$1': stderr not one line"; cat "$T/err"; }
  [[ "$(cat "$T/err")" == "$2" ]] && ok || { bad "HARNESS_ISA='$1': message"; echo "  got:  $(cat "$T/err")"; echo "  want: $2"; }
  [[ ! -s "$T/out" && ! -e "$T/rejected" ]] && ok || bad "HARNESS_ISA='$1': something was written"
}
for w in sse2 AVX2 avx-512 " avx" avx512f 1; do
  rejected "$w" "harness: error: HARNESS_ISA: unknown instruction set '$w' (expected scalar, avx, avx2 or avx512)"
done
# Every command checks it, `list` and `bench` too.
HARNESS_ISA=bogus "$H" list >/dev/null 2>"$T/err"; rc=$?
[[ $rc -eq 2 ]] && grep -q "^harness: error: HARNESS_ISA: unknown instruction set 'bogus'" "$T/err" && ok \
  || bad "list with HARNESS_ISA=bogus: exit $rc"
HARNESS_ISA=bogus "$H" bench --quick --out "$T/b.csv" >/dev/null 2>"$T/err"; rc=$?
[[ $rc -eq 2 && ! -e "$T/b.csv" ]] && ok || bad "bench with HARNESS_ISA=bogus: exit $rc"

# The levels this processor runs: all give the same state hash (one short run each); the others
# are rejected by name. scalar always runs.
hash_of() { sed -n 's/.*"state_hash": "\([0-9a-f]*\)".*/\1/p' "$1/summary.json" 2>/dev/null; }
supported=(); unsupported=()
for i in scalar avx avx2 avx512; do
  if HARNESS_ISA=$i "$H" list >/dev/null 2>"$T/err"; then supported+=("$i"); else unsupported+=("$i"); fi
done
[[ " ${supported[*]} " == *" scalar "* ]] && ok || bad "scalar is not accepted"
want=""
for i in "${supported[@]}"; do
  HARNESS_ISA=$i "$H" run cylinder_press --out "$T/run.$i" --steps 20 --set 'references.solvers=[]' \
    --set output.frames_every=0 --quiet 2>"$T/err" && ok || { bad "run with HARNESS_ISA=$i"; cat "$T/err"; }
  h=$(hash_of "$T/run.$i")
  [[ -n "$h" ]] && ok || bad "HARNESS_ISA=$i: no state hash"
  [[ -z "$want" ]] && want=$h
  [[ "$h" == "$want" ]] && ok || bad "HARNESS_ISA=$i: state hash $h, scalar gave $want"
done
# An empty value is no value: the default level.
HARNESS_ISA= "$H" run cylinder_press --out "$T/run.default" --steps 20 --set 'references.solvers=[]' \
  --set output.frames_every=0 --quiet 2>/dev/null && [[ "$(hash_of "$T/run.default")" == "$want" ]] && ok \
  || bad "empty HARNESS_ISA"
for i in "${unsupported[@]}"; do
  rejected "$i" "harness: error: HARNESS_ISA: this processor cannot run $i (it can run $(IFS=,; echo "${supported[*]}" | sed 's/,/, /g'))"
done
[[ ${#unsupported[@]} -eq 0 ]] && echo "note: this processor runs every level; the message for one it cannot run is tested in tests/core/test_cpu.cpp"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
