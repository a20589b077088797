#!/usr/bin/env bash
# Reproducible to the bit across processes (and thread counts, where the build has threads):
# every bundled scene, shortened, gives the same state_hash in two separate runs.
# Usage: test_hash.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
pass=0; fail=0
hash_of() { sed -n 's/.*"state_hash": "\([0-9a-f]*\)".*/\1/p' "$1/summary.json"; }
for f in "$SRC"/experiments/scenes/*.json "$SRC"/experiments/scenes/hard/*.json; do
  n=$(basename "$f" .json)
  HARNESS_THREADS=1 "$H" run "$f" --out "$T/$n.a" --steps 60 --set 'references.solvers=[]' --quiet 2>/dev/null
  HARNESS_THREADS=1 "$H" run "$f" --out "$T/$n.b" --steps 60 --set 'references.solvers=[]' --quiet 2>/dev/null
  HARNESS_THREADS=2 "$H" run "$f" --out "$T/$n.c" --steps 60 --set 'references.solvers=[]' --quiet 2>/dev/null
  a=$(hash_of "$T/$n.a"); b=$(hash_of "$T/$n.b"); c=$(hash_of "$T/$n.c")
  if [[ -n "$a" && "$a" == "$b" && "$a" == "$c" ]]; then pass=$((pass+1)); else echo "FAIL: $n: $a $b $c"; fail=$((fail+1)); fi
  # References only measure: the hash with them equals the hash without.
  if [[ "$n" == sphere_collision ]]; then
    "$H" run "$f" --out "$T/$n.r" --steps 60 --set 'references.solvers=["cgal","fcl","ccd"]' --quiet 2>/dev/null
    r=$(hash_of "$T/$n.r")
    if [[ "$r" == "$a" ]]; then pass=$((pass+1)); else echo "FAIL: references changed the hash: $r vs $a"; fail=$((fail+1)); fi
  fi
done
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
