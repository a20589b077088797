#!/usr/bin/env bash
# The main job: installs what is missing, builds, runs the bundled scenes into results/.
# Usage: scripts/reproduce.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    *) echo "reproduce.sh: unknown option '$a'" >&2; exit 2 ;;
  esac
done
scripts/install-deps.sh
scripts/build.sh release
H=build/bin/harness
out=results/runs
mkdir -p "$out"
extra=()
[[ $quick -eq 1 ]] && extra=(--steps 200)
for scene in sphere_collision cylinder_press implant_expansion; do
  echo "reproduce: $scene"
  "$H" run "$scene" --out "$out/$scene" --quiet "${extra[@]}"
done
echo "reproduce: done; outputs in $out/"
