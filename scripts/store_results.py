#!/usr/bin/env python3
"""Stores run folders under a results tree the way they are committed (results/README.md, "What
is committed"): every steps.csv becomes steps.csv.gz holding the columns a reproduced state
reproduces, its wall times (t_*_us) go to timing.csv beside it (keyed by step and pair; not
committed), and the surfaces.csv of a run under a runs/ folder or of a reference's level (levels/N/)
is gzipped. The .gz files are
deterministic (no name or time in their headers): the same run stored twice gives the same bytes.
Folders already stored are left as they are. A reference's own surfaces.csv (the one `harness run
--compare` reads) stays plain.

Usage: store_results.py [RESULTS_DIR]   (default: results; results/sweeps/ is skipped)
"""

import csv
import io
import os
import sys

from harness_results import reader

SKIP = ("sweeps",)


def is_timing(name):
    return name.startswith("t_") and name.endswith("_us")


def csv_text(header, rows):
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    return out.getvalue()


def store_steps(folder):
    """folder/steps.csv -> steps.csv.gz (+ timing.csv where its wall times were still in it)."""
    src = os.path.join(folder, "steps.csv")
    with open(src, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return False
    header = rows[0]
    keep = [i for i, c in enumerate(header) if not is_timing(c)]
    timing = [i for i, c in enumerate(header) if is_timing(c)]
    if timing:
        keys = [header.index(k) for k in reader.TIMING_KEYS if k in header]
        with open(os.path.join(folder, "timing.csv"), "w", newline="") as f:
            f.write(csv_text([header[i] for i in keys + timing], [[r[i] for i in keys + timing] for r in rows[1:]]))
    reader.write_gz(src + ".gz", csv_text([header[i] for i in keep], [[r[i] for i in keep] for r in rows[1:]]))
    os.remove(src)
    return True


def store_plain(path):
    with open(path, newline="") as f:
        text = f.read()
    reader.write_gz(path + ".gz", text)
    os.remove(path)


def store(root):
    """Stores every run folder under root; returns the number of files it rewrote."""
    n = 0
    for d, subdirs, files in os.walk(root):
        subdirs[:] = sorted(s for s in subdirs if not (d == root and s in SKIP))
        if "steps.csv" in files:
            n += store_steps(d)
        parts = os.path.relpath(d, root).split(os.sep)
        if "surfaces.csv" in files and ("runs" in parts[:-1] or "levels" in parts[:-1]):
            store_plain(os.path.join(d, "surfaces.csv"))
            n += 1
    return n


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    if not os.path.isdir(root):
        sys.exit("store_results: %s: no such folder" % root)
    print("store_results: %d files stored under %s" % (store(root), root))


if __name__ == "__main__":
    main()
