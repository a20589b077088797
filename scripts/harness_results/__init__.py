"""The result scripts' package (scripts/study.py, claims.py, tables.py, figures.py, counts.py,
plot_bench.py, thresholds.py, prune_frames.py, device_state_check.py are its command lines: each
parses its arguments and calls a module here).

  reader.py    the one CSV reader (numbers as floats, NaN when missing) and the one place that knows
               summary.json's key paths (accessors: window figures, stability inputs, timings, pair)
  runs.py      the runs of scripts/reproduce.sh (results/runs/), their frames (prune_frames)
  figures.py   the runs' figures (scripts/figures.py)
  tables.py    the runs' tables (scripts/tables.py)
  bench.py     harness bench's figure and tables (scripts/plot_bench.py)
  thresholds.py   the CI accuracy thresholds, measured (scripts/thresholds.py)
  state_check.py  the GPU's final states against the CPU's (scripts/device_state_check.py)
  rules.py     the studies' written rules: stability as the study files record it, the defaults'
               choice, the front
  episodes.py  a run's penetration episodes against claim (b)'s criteria
  runner.py    `harness run` / `harness reference` as child processes: cached by summary.json, -j, repeats;
               the warning for a run stopped before its forcing ended
  methods.py   the user's methods as data (study.py --method NAME=KEY=JSON,...): parsed, recorded
  needs.py     numpy and matplotlib, or one line and exit 2 (the command lines that draw)
  style.py     the figure style: pyplot set up, printed sizes, colours, save, heat maps, labels
  writers.py   CSV, Markdown and LaTeX tables (write_table: .md, .csv and .tex at once)
  counts.py    the counts the report quotes (tables/counts.tex)
  studies/     one module per study (study.py NAME; run_all runs them in turn)
  judge/       the claims (claims.py): choices.py (every analysis choice), measure.py (a run: failed,
               stability, error and time with intervals), claims.py (each claim's declared
               comparisons), state.py (SUMMARY.md, claims.md, specifications.csv, the macros)
docs/architecture.md ("How to add") says how to add a study and a claim.
"""
