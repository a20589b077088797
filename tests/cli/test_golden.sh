#!/usr/bin/env bash
# Golden state hashes (as Box2D's determinism test): every bundled scene, shortened, must end in
# the state hash recorded in tests/golden/state_hashes.json at every instruction set level the
# processor supports (HARNESS_ISA, core/cpu.hpp: the best one with one thread and with two, the
# others with one), and with the references on (they only measure). A changed hash means the
# simulated states changed: if that is meant, re-record with scripts/update-golden.sh and say why
# in the commit. (The hashes assume x86-64 with AVX2 and libmvec: see the golden file.)
# Usage: test_golden.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
PYTHON="${PYTHON:-/usr/bin/python3}"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
golden="$SRC/tests/golden/state_hashes.json"
mapfile -t rows < <("$PYTHON" -c '
import json, sys
g = json.load(open(sys.argv[1]))
for n, v in g["scenes"].items(): print(n, v["steps"], v["state_hash"])' "$golden")
if [[ ${#rows[@]} -eq 0 ]]; then echo "FAIL: $golden lists no scene"; exit 1; fi
# Every bundled scene has a golden hash (a new scene must be recorded).
for f in "$SRC"/experiments/scenes/*.json "$SRC"/experiments/scenes/hard/*.json "$SRC"/experiments/scenes/bullet/*.json; do
  rel=${f#"$SRC"/experiments/scenes/}; n=${rel%.json}
  printf '%s\n' "${rows[@]}" | grep -q "^$n " || { echo "FAIL: $n has no golden hash (scripts/update-golden.sh)"; exit 1; }
done
# The levels this processor runs (HARNESS_ISA rejects the others at start-up), lowest first.
isas=()
for i in scalar avx avx2 avx512; do
  HARNESS_ISA=$i "$H" list >/dev/null 2>&1 && isas+=("$i")
done
if [[ ${#isas[@]} -eq 0 ]]; then echo "FAIL: no instruction set level accepted (harness list)"; exit 1; fi
best=${isas[${#isas[@]}-1]}
echo "levels: ${isas[*]}"
hash_of() { sed -n 's/.*"state_hash": "\([0-9a-f]*\)".*/\1/p' "$1/summary.json" 2>/dev/null; }
pass=0; fail=0
check() {  # check LABEL EXPECTED DIR
  local got; got=$(hash_of "$3")
  if [[ "$got" == "$2" ]]; then pass=$((pass+1)); else echo "FAIL: $1: state hash ${got:-missing}, golden $2"; fail=$((fail+1)); fi
}
for row in "${rows[@]}"; do
  read -r n steps want <<<"$row"
  f="$SRC/experiments/scenes/$n.json"
  d="$T/${n//\//_}"
  for isa in "${isas[@]}"; do
    ths=(1); [[ $isa == "$best" ]] && ths=(1 2)
    for th in "${ths[@]}"; do
      HARNESS_ISA=$isa HARNESS_THREADS=$th "$H" run "$f" --out "$d.$isa.t$th" --steps "$steps" \
        --set 'references.solvers=[]' --set 'output.frames_every=0' --quiet 2>"$d.$isa.t$th.err"
      check "$n ($isa, threads $th)" "$want" "$d.$isa.t$th"
    done
  done
  # References only measure: the hash with them equals the golden one.
  if [[ "$n" == sphere_collision ]]; then
    HARNESS_ISA=$best "$H" run "$f" --out "$d.ref" --steps "$steps" --set 'references.solvers=["cgal","fcl","ccd"]' \
      --set 'output.frames_every=0' --quiet 2>/dev/null
    check "$n (references on)" "$want" "$d.ref"
  fi
done
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
