"""The studies of the report, one module each, all judged by the error against a converged reference
solution (rules.py states the definitions). Each module has `run(a)` (runs its configurations
through runner.py, writes its CSV, tables and figures) and, when it draws figures, `plots(a)` (the
figures again from its CSV, nothing run: study.py --plots-only). `a` is study.py's parsed command line.

To add a study: a module here with `run(a)` (and `plots(a)`), its name in ORDER, its outputs in
results/README.md.
"""

import importlib

# The order of `study.py all`.
ORDER = ["references", "accuracy", "ablation", "convergence", "refinement", "realtime", "swap", "region", "orient",
         "bullet"]


def module(name):
    """The module of study `name`."""
    return importlib.import_module("." + name, __name__)
