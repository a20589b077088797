"""Writing tables: the studies' CSV files (numbers to 6 significant digits, NaN as an empty cell, the
reader's convention), Markdown and LaTeX tables, LaTeX escaping. Deterministic: no dates."""

import csv
import math


def tex_escape(v):
    """A value as LaTeX text: the characters LaTeX treats specially are escaped."""
    return (str(v).replace("\\", "\\textbackslash{}").replace("_", "\\_").replace("%", "\\%")
            .replace("&", "\\&").replace("#", "\\#"))


def fmt(v, spec):
    """v formatted by `spec`, "n/a" when missing (None or NaN)."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "n/a"
    return format(v, spec)


def cell(v):
    if isinstance(v, float):
        return "" if math.isnan(v) else "%.6g" % v
    return v


def write_csv(path, rows, cols):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(cols)
        for r in rows:
            w.writerow([cell(r.get(c, "")) for c in cols])


def md_table(rows, cols, heads):
    def show(v):
        if isinstance(v, float):
            return "" if math.isnan(v) else "%.4g" % v
        return str(v)
    out = ["| " + " | ".join(heads) + " |", "|" + "---|" * len(heads)]
    for r in rows:
        out.append("| " + " | ".join(show(r.get(c, "")) for c in cols) + " |")
    return "\n".join(out) + "\n"


def tex_table(rows, cols, heads, caption):
    def show(v):
        if isinstance(v, float):
            return "--" if math.isnan(v) else "%.3g" % v
        return tex_escape(v)
    out = ["\\begin{tabular}{" + "l" * 2 + "r" * (len(cols) - 2) + "}", "\\toprule", " & ".join(heads) + " \\\\",
           "\\midrule"]
    for r in rows:
        out.append(" & ".join(show(r.get(c, "")) for c in cols) + " \\\\")
    out += ["\\bottomrule", "\\end{tabular}"]
    return "% " + caption + " (made by scripts/study.py)\n" + "\n".join(out) + "\n"


def write_text(path, text):
    with open(path, "w") as f:
        f.write(text)
