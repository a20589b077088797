"""Files as the results tree stores them (results/README.md, "What is committed"): a CSV file may be
committed gzipped (NAME.csv.gz beside or instead of NAME.csv). `stored` finds the form that is
there, `open_text` reads either, `write_gz` writes the gzipped form so that the same text gives the
same bytes. reader.py (the one CSV reader) and scripts/store_results.py use them."""

import gzip
import os


def stored(path):
    """The file `path` as stored: `path` itself, else `path`.gz (committed copies are gzipped); None
    when neither exists."""
    for p in (path, path + ".gz"):
        if os.path.isfile(p):
            return p
    return None


def open_text(path):
    """`path` (or its stored .gz form, see `stored`) opened for reading text; OSError when neither is
    there."""
    p = stored(path)
    if p is None:
        raise FileNotFoundError("%s: no such file (nor %s.gz)" % (path, path))
    return gzip.open(p, "rt", newline="") if p.endswith(".gz") else open(p, newline="")


def write_gz(path, text):
    """`text` into `path` (ending in .gz) gzipped so that the same text gives the same bytes (no
    name, no time in the header)."""
    with open(path, "wb") as raw:
        with gzip.GzipFile(filename="", mode="wb", fileobj=raw, mtime=0, compresslevel=9) as g:
            g.write(text.encode())
