#!/usr/bin/env bash
# Installs the Debian 12 packages the harness needs, only those missing. slurmctld, slurmd,
# slurm-client and munge are for cli:test_slurm, which configures and starts its own single-node
# cluster in a temporary folder (no system-wide Slurm or munge configuration is written);
# python3-pytest for scripts:pytest (tests/scripts/: the result scripts' rules); python3-dev and
# pybind11-dev for the Python module (python/, docs/python.md) and its tests (python:pytest).
# Usage: scripts/install-deps.sh [--latex]   (--latex adds what paper/ needs)
set -euo pipefail
pkgs=(g++ cmake ninja-build make git pkg-config libeigen3-dev libfcl-dev libccd-dev libcgal-dev
      libgmp-dev libmpfr-dev libboost-dev libbullet-dev catch2 nlohmann-json3-dev libcli11-dev
      python3 python3-dev pybind11-dev python3-matplotlib python3-numpy python3-meshio python3-jsonschema python3-pytest snakemake
      slurmctld slurmd slurm-client munge)
if [[ "${1:-}" == "--latex" ]]; then
  pkgs+=(texlive-latex-base texlive-latex-recommended texlive-latex-extra latexmk poppler-utils)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#pkgs[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
[[ $(id -u) -eq 0 ]] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
