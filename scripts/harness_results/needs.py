"""What the result scripts need beyond the standard library: numpy and matplotlib (Debian's
python3-numpy, python3-matplotlib). A command line that draws calls numpy_and_matplotlib first, so
that an interpreter without them gets one line and exit status 2, not a traceback half-way."""

import importlib.util
import sys


def missing(modules=("numpy", "matplotlib")):
    """The modules of `modules` this interpreter cannot import."""
    out = []
    for m in modules:
        try:
            found = importlib.util.find_spec(m) is not None
        except (ImportError, ValueError):
            found = False
        if not found:
            out.append(m)
    return out


def numpy_and_matplotlib(program):
    """Exit 2 with one line on stderr when numpy or matplotlib is missing."""
    if missing():
        print("%s: needs numpy and matplotlib (Debian's python3-numpy, python3-matplotlib); run it with "
              "/usr/bin/python3 or set PYTHON" % program, file=sys.stderr)
        sys.exit(2)
