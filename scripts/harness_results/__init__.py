"""The result scripts' package (scripts/study.py, claims.py, tables.py, figures.py, counts.py,
plot_bench.py, thresholds.py, prune_frames.py are its command lines).

  reader.py    the one CSV reader (numbers as floats, NaN when missing) and the one place that knows
               summary.json's key paths (accessors: window figures, stability inputs, timings, pair)
  runs.py      the runs of scripts/reproduce.sh (results/runs/), their frames
  rules.py     the written rules: stability, the defaults' choice, the front, the claims' comparisons
               and verdicts (with "inconclusive")
  runner.py    `harness run` / `harness reference` as child processes: cached by summary.json, -j, repeats
  style.py     the figure style: pyplot set up, printed sizes, colours, save, heat maps, labels
  writers.py   CSV, Markdown and LaTeX tables
  counts.py    the counts the report quotes (tables/counts.tex)
  studies/     one module per study (study.py NAME)
  claims/      one module per claim of the paper (claims.py)
docs/architecture.md ("The Python pipeline") says how to add a study and a claim.
"""
