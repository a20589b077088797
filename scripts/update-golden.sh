#!/usr/bin/env bash
# Records the golden state hashes (tests/golden/state_hashes.json) that tests/cli/test_golden.sh
# compares every bundled scene against: each scene run for STEPS steps (or fewer, its own count),
# one thread, no references (they never change the state), no frames.
#
# The file changes only on purpose: run this script after a change that is meant to change the
# simulated states, and say in the commit message why they changed.
# Usage: scripts/update-golden.sh [HARNESS]   (default build/bin/harness)
set -euo pipefail
cd "$(dirname "$0")/.."
H="${1:-build/bin/harness}"
PYTHON="${PYTHON:-/usr/bin/python3}"
steps=400
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
names=()
for f in experiments/scenes/*.json experiments/scenes/hard/*.json experiments/scenes/bullet/*.json; do
  rel=${f#experiments/scenes/}
  n=${rel%.json}
  HARNESS_THREADS=1 "$H" run "$f" --out "$T/${n//\//_}" --steps "$steps" --set 'references.solvers=[]' \
    --set 'output.frames_every=0' --quiet
  names+=("$n")
done
"$PYTHON" - "$T" "$steps" "${names[@]}" > tests/golden/state_hashes.json <<'PY'
import json, os, sys
tmp, steps, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
scenes = {}
for n in names:
    with open(os.path.join(tmp, n.replace("/", "_"), "summary.json")) as f:
        s = json.load(f)
    scenes[n] = {"steps": s["steps_run"], "state_hash": s["state_hash"]}
print(json.dumps({"comment": "Golden state hashes: written by scripts/update-golden.sh, checked by "
                  "tests/cli/test_golden.sh at every instruction set level (HARNESS_ISA). Change only on purpose, "
                  "with the reason in the commit. They assume x86-64 with AVX2 and glibc's libmvec: the exponential "
                  "spring law takes libmvec's expm1, whose last bits differ from std::expm1's, whenever the processor "
                  "has AVX2, whatever the level (core/cpu.hpp).",
                  "steps": steps, "threads": 1, "scenes": scenes}, indent=2))
PY
echo "update-golden: $(( ${#names[@]} )) scenes written to tests/golden/state_hashes.json"
