#!/usr/bin/env bash
# Configures and builds the harness. Usage: scripts/build.sh [release|debug|asan]
# Build folder: build/ (release), build-debug/, build-asan/. Uses 2 jobs (CGAL is memory heavy).
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
case "$preset" in
  release) dir=build ;;
  debug) dir=build-debug ;;
  asan) dir=build-asan ;;
  *) echo "build.sh: unknown preset '$preset' (release, debug, asan)" >&2; exit 2 ;;
esac
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
if [[ ! -f "$dir/CMakeCache.txt" ]]; then
  cmake --preset "$preset" "${gen[@]}"
fi
cmake --build "$dir" -j "${JOBS:-2}"
