#!/usr/bin/env bash
# The main job: installs what is missing, builds, runs the bundled scenes into results/, then
# makes the figures, tables and the claims check from them (results/README.md lists every file).
# Usage: scripts/reproduce.sh [--quick] [--paper]
#   --quick  300 steps per run instead of the scenes' own (a smoke run, about three minutes)
#   --paper  also installs LaTeX (Debian packages) and builds paper/main.pdf
# Environment: PYTHON (default /usr/bin/python3: Debian's matplotlib and numpy);
#   HARNESS=path uses that harness binary and skips the install and build steps.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
paper=0
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    --paper) paper=1 ;;
    *) echo "reproduce.sh: unknown option '$a'" >&2; exit 2 ;;
  esac
done
PYTHON="${PYTHON:-/usr/bin/python3}"
export PYTHON
start=$(date +%s)
if [[ -n "${HARNESS:-}" ]]; then
  H="$HARNESS"
else
  scripts/install-deps.sh
  scripts/build.sh release
  H=build/bin/harness
fi
out=results/runs
mkdir -p "$out"
extra=()
[[ $quick -eq 1 ]] && extra=(--steps 300)

# run FOLDER SCENE ELIMINATOR [--set ...]: one harness run into results/runs/FOLDER.
run() {
  local folder="$1" scene="$2" elim="$3"
  shift 3
  echo "reproduce: $folder"
  rm -rf "${out:?}/$folder"
  "$H" run "$scene" --out "$out/$folder" --quiet --set "contacts.0.eliminator=\"$elim\"" "$@" "${extra[@]}"
}
# Every scene with both eliminators, references (CGAL, FCL) as the scenes set them. Each scene
# keeps its force setting for both eliminators (auto: the defaults chosen from the ablation,
# results/tables/ablation.md). The implant is also run with a constant force, and the cylinder
# with the least energetic constant force that removes its penetration (unstable by the
# ablation's criterion: the price of elimination there).
for elim in line plane; do
  run "sphere_collision_$elim" sphere_collision "$elim"
  run "cylinder_press_$elim" cylinder_press "$elim"
  run "cylinder_press_f003_$elim" cylinder_press "$elim" --set contacts.0.force=0.03 --set contacts.0.voxel_size=0.008
  run "implant_expansion_$elim" implant_expansion "$elim"
  run "implant_expansion_f002_$elim" implant_expansion "$elim" --set contacts.0.force=0.02
done
rm -rf results/runs/sphere_collision results/runs/cylinder_press results/runs/implant_expansion

# Keep only the frames the figures and tables use (results stay small).
"$PYTHON" scripts/prune_frames.py results
"$PYTHON" scripts/figures.py results
"$PYTHON" scripts/tables.py results
"$PYTHON" scripts/claims.py results
# What accuracy costs in time, ablations of force and voxel size, convergence (issue 6). The
# per-point run folders stay in results/sweeps/ (not committed); the merged CSV, figures and
# tables are in results/.
study=(--harness "$H" --results results)
[[ $quick -eq 1 ]] && study+=(--quick)
"$PYTHON" scripts/study.py all "${study[@]}"
echo "reproduce: results written in $(( $(date +%s) - start )) s"

if [[ $paper -eq 1 ]]; then
  scripts/install-deps.sh --latex || echo "reproduce: LaTeX could not be installed" >&2
  if command -v latexmk >/dev/null && command -v pdflatex >/dev/null; then
    (cd paper && latexmk -pdf -interaction=nonstopmode -halt-on-error -quiet main.tex)
    echo "reproduce: paper/main.pdf built"
  else
    echo "reproduce: latexmk/pdflatex missing: paper/main.pdf not built (results/ are complete)" >&2
    exit 1
  fi
fi
echo "reproduce: done in $(( $(date +%s) - start )) s; outputs in results/"
