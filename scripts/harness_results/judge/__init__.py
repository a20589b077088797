"""The judge of the paper's claims (scripts/claims.py). Four floors, each reading only the ones before it:

  choices.py   every analysis choice that remains, one declarative table (the value as written, each
               alternative with one line of why), passed as a Spec
  measure.py   a run from a study row: whether it failed, its stability class, its error and time
               with their intervals (the window's range and the reference's floor; an ensemble's
               spread where results/ensembles.csv has one; the repeats' range)
  claims.py    each claim's comparison declared before the data, its effects per scene and the
               verdict from their intervals
  state.py     results/SUMMARY.md, claims.md, specifications.csv and the report's macros

docs/architecture.md ("How to add", "A claim") says how to add a claim.
"""
