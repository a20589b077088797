#!/usr/bin/env bash
# The main job: installs what is missing, builds, runs the paper's voxel model on the bundled
# scenes into results/runs/, then makes the figures, tables and the claims check from them and from
# the committed study CSV files (results/README.md lists every file).
# Usage: scripts/reproduce.sh [--quick] [--paper] [--studies]
#        scripts/reproduce.sh --paper-only
#   --quick       300 steps per run instead of the scenes' own (a smoke run, seconds)
#   --paper       also installs LaTeX (Debian packages) and builds paper/main.pdf
#   --studies     also reruns the studies (scripts/study.py ablation accuracy convergence refinement
#                 realtime realtime_grid swap region orient: hours on two cores; each run is cached in
#                 results/sweeps/, so an interrupted study resumes). Without it the study CSV files
#                 committed in results/ are used as they are.
#   --paper-only  builds paper/main.pdf from the committed results alone: no build, no harness, no
#                 runs (minutes, not hours), and nothing written into results/ or paper/ but
#                 paper/main.pdf: in a folder of its own (build/paper-only/, a copy of results/ and
#                 paper/) it redraws every figure from the committed runs and CSVs (figures.py;
#                 plot_bench.py; study.py accuracy ablation convergence realtime realtime_grid --plots-only),
#                 rewrites tables/counts.tex (counts.py) and runs latexmk, then copies main.pdf to
#                 paper/. Installs LaTeX and matplotlib if missing (install-deps.sh --latex). The
#                 tables are the committed ones.
# The runs go two at a time (this machine has two cores); each is one thread.
# Environment: PYTHON (default /usr/bin/python3: Debian's matplotlib and numpy);
#   HARNESS=path uses that harness binary and skips the install and build steps.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
paper=0
paper_only=0
studies=0
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    --paper) paper=1 ;;
    --paper-only) paper_only=1 ;;
    --studies) studies=1 ;;
    *) echo "reproduce.sh: unknown option '$a'" >&2; exit 2 ;;
  esac
done
if [[ $paper_only -eq 1 && ( $quick -eq 1 || $paper -eq 1 || $studies -eq 1 ) ]]; then
  echo "reproduce.sh: --paper-only runs nothing; it takes no other option" >&2
  exit 2
fi
PYTHON="${PYTHON:-/usr/bin/python3}"
export PYTHON
start=$(date +%s)

# build_paper [DIR]: DIR/main.pdf (default paper/) from what DIR/../results holds now (LaTeX
# installed when missing).
build_paper() {
  local dir="${1:-paper}"
  if ! command -v latexmk >/dev/null || ! command -v pdflatex >/dev/null; then
    scripts/install-deps.sh --latex || echo "reproduce: LaTeX could not be installed" >&2
  fi
  if command -v latexmk >/dev/null && command -v pdflatex >/dev/null; then
    # The same sources and results give the same PDF: its dates are those of the last commit of
    # results/ and paper/ sources (pdfTeX's SOURCE_DATE_EPOCH), not the build's.
    local epoch
    epoch=$(git log -1 --format=%ct -- results paper/main.tex 2>/dev/null || true)
    (cd "$dir" && SOURCE_DATE_EPOCH="${epoch:-0}" FORCE_SOURCE_DATE=1 latexmk -pdf -interaction=nonstopmode -halt-on-error -quiet main.tex)
    echo "reproduce: $dir/main.pdf built"
    # A rendered page of the claims section (its first page, from the label in main.aux).
    local page
    page=$(sed -n 's/^\\newlabel{sec:claims}{{[^}]*}{\([0-9]*\)}.*/\1/p' "$dir/main.aux" | head -1)
    if [[ -n "$page" ]] && command -v pdftoppm >/dev/null; then
      mkdir -p "$dir/preview"
      pdftoppm -f "$page" -l "$page" -r 90 -png -singlefile "$dir/main.pdf" "$dir/preview/claims"
      echo "reproduce: $dir/preview/claims.png (page $page)"
    fi
  else
    echo "reproduce: latexmk/pdflatex missing: paper/main.pdf not built (results/ are complete)" >&2
    exit 1
  fi
}

if [[ $paper_only -eq 1 ]]; then
  if ! command -v latexmk >/dev/null || ! command -v pdflatex >/dev/null ||
     ! "$PYTHON" -c "import matplotlib, numpy" 2>/dev/null; then
    scripts/install-deps.sh --latex
  fi
  # A folder of its own: the committed results and the report's sources copied (not the cards'
  # or the studies' cached runs), everything drawn and built there; only main.pdf comes back.
  stage=build/paper-only
  rm -rf "$stage" && mkdir -p "$stage"
  tar -cf - --exclude='results/cards/*/runs/*/*' --exclude='results/sweeps' --exclude='paper/*.aux' results paper \
    | tar -C "$stage" -xf -
  # Figures from the committed data only (none of these needs the harness), drawn at the size
  # the report prints them; then the counts the text quotes.
  "$PYTHON" scripts/figures.py "$stage/results"
  [[ -f "$stage/results/bench.csv" ]] && "$PYTHON" scripts/plot_bench.py "$stage/results/bench.csv" "$stage/results"
  "$PYTHON" scripts/study.py accuracy ablation convergence realtime realtime_grid --plots-only --results "$stage/results"
  "$PYTHON" scripts/counts.py "$stage/results"
  build_paper "$stage/paper"
  cp "$stage/paper/main.pdf" paper/main.pdf
  echo "reproduce: paper/main.pdf from $stage/; done in $(( $(date +%s) - start )) s (from the committed results)"
  exit 0
fi
if [[ -n "${HARNESS:-}" ]]; then
  H="$HARNESS"
else
  scripts/install-deps.sh
  scripts/build.sh release
  H=build/bin/harness
fi
out=results/runs
mkdir -p "$out"
# Each run settles as the scene says (time.settle: the same tolerance and cap as the studies and the
# references), so that its final window is judged as theirs are.
extra=()
[[ $quick -eq 1 ]] && extra=(--steps 300)

# run FOLDER SCENE ELIMINATOR FORCE [--set ...]: the paper's voxel model (one-sided, the scene's
# voxel size) on a bundled scene, measured by CGAL every 10 steps and compared with the scene's
# committed reference solution (results/references/), into results/runs/FOLDER; its stderr into
# results/runs/FOLDER.log while it runs (removed when it succeeds).
# The runs are one-sided (the paper's model): where the scene has a one-sided reference
# (results/references/SCENE_one_sided) it is measured beside the two-sided one (--compare-also), so
# every run is judged against the reference of its kind with the other beside.
run() {
  local folder="$1" scene="$2" elim="$3" force="$4"
  shift 4
  rm -rf "${out:?}/$folder"
  local also=()
  [[ -f "results/references/${scene}_one_sided/summary.json" ]] && also=(--compare-also "results/references/${scene}_one_sided")
  if HARNESS_THREADS=1 "$H" run "$scene" --out "$out/$folder" --quiet --compare "results/references/$scene" "${also[@]}" \
    --set 'contacts.0.detector="voxel"' --set "contacts.0.eliminator=\"$elim\"" --set "contacts.0.force=$force" \
    --set contacts.0.two_sided=false --set 'references.solvers=["cgal"]' --set references.every=10 --set output.format=vtk \
    "$@" "${extra[@]}" 2>"$out/$folder.log"; then
    echo "reproduce: $folder"
    rm -f "$out/$folder.log"
  else
    echo "reproduce: $folder failed (exit $?): $out/$folder.log" >&2
    return 1
  fi
}
# Every scenario with both eliminators and the automatic force; the cylinder and the implant also
# with a constant 0.003 N per contact (the paper's constant force, within the equal-footing range
# of the studies). The bundled scenes' own default (exact detection, penalty) is what the
# references and the studies measure against. Two runs at a time.
jobs=()
for elim in line plane; do
  jobs+=("sphere_collision_$elim sphere_collision $elim \"auto\"")
  jobs+=("cylinder_press_$elim cylinder_press $elim \"auto\"")
  jobs+=("cylinder_press_f0003_$elim cylinder_press $elim 0.003")
  jobs+=("implant_expansion_$elim implant_expansion $elim \"auto\"")
  jobs+=("implant_expansion_f0003_$elim implant_expansion $elim 0.003")
done
failed=0
running=0
for j in "${jobs[@]}"; do
  eval "set -- $j"
  run "$@" &
  running=$((running + 1))
  if [[ $running -ge 2 ]]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
done
while [[ $running -gt 0 ]]; do
  wait -n || failed=1
  running=$((running - 1))
done
if [[ $failed -ne 0 ]]; then
  echo "reproduce: a run failed (its log is in $out/)" >&2
  exit 1
fi

# Keep only the frames the figures and tables use (they are not committed: results/README.md).
"$PYTHON" scripts/prune_frames.py results
"$PYTHON" scripts/figures.py results
"$PYTHON" scripts/tables.py results
# The runs as committed: steps.csv.gz without the wall times (timing.csv, not committed), so a rerun
# that reproduces the states changes only timing figures (results/README.md, "What is committed").
"$PYTHON" scripts/store_results.py results
"$PYTHON" scripts/claims.py results
# The studies, all judged against the committed reference solutions (results/references/;
# `scripts/study.py references` recomputes them: hours), only with --studies (hours; the per-point
# run folders stay in results/sweeps/, not committed, and are reused); the claims are judged again
# on what they wrote.
if [[ $studies -eq 1 ]]; then
  study=(--harness "$H" --results results)
  [[ $quick -eq 1 ]] && study+=(--quick)
  "$PYTHON" scripts/study.py ablation accuracy convergence refinement realtime realtime_grid swap region orient "${study[@]}"
  "$PYTHON" scripts/claims.py results
fi
echo "reproduce: results written in $(( $(date +%s) - start )) s"

# The counts the report quotes (runs, configurations, points), from what was just made.
"$PYTHON" scripts/counts.py results

if [[ $paper -eq 1 ]]; then
  build_paper
fi
echo "reproduce: done in $(( $(date +%s) - start )) s; outputs in results/"
