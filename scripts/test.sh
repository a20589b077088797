#!/usr/bin/env bash
# Installs what is missing, builds, runs every test (ctest: Catch2, command line, fuzz replay, and
# scripts:pytest, the result scripts' rules in tests/scripts/; python:pytest, the Python module in
# tests/python/). Exit non-zero on any failure.
# Usage: scripts/test.sh [--sanitize]   (--sanitize: AddressSanitizer + UBSan build)
set -euo pipefail
cd "$(dirname "$0")/.."
preset=release
dir=build
if [[ "${1:-}" == "--sanitize" ]]; then preset=asan; dir=build-asan; fi
scripts/install-deps.sh
scripts/build.sh "$preset"
cd "$dir"
ctest --output-on-failure -j "${JOBS:-2}" --timeout 1200
