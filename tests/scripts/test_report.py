"""The report says what its data say: paper/main.tex types at most MAX_TYPED decimal numbers by hand
(constants such as 0.9 dt_crit; every measured number comes from a macro written from results/), and
every macro it uses is defined (by the generated macro files or by the report itself)."""

import os
import re

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
MAIN = os.path.join(ROOT, "paper", "main.tex")
MACRO_FILES = [os.path.join(ROOT, "results", "tables", f) for f in ("claims_macros.tex", "counts.tex")]
MAX_TYPED = 15

# A decimal number (digits, a point, digits) that is not a length (0.49\textwidth, 2.2cm).
DECIMAL = re.compile(r"(?<![\w.])\d+\.\d+(?![\d.])(?!\s*(?:\\textwidth|\\linewidth|\\columnwidth|cm|mm\b(?=[,\]])|em|ex|pt))")


def prose_lines(text):
    """The report's lines without comments, \\input and \\includegraphics (file names and sizes)."""
    out = []
    for line in text.splitlines():
        line = re.sub(r"(?<!\\)%.*", "", line)
        if re.search(r"\\(input|includegraphics|usepackage|documentclass|setlength|graphicspath)", line):
            continue
        out.append(line)
    return out


def typed_decimals(text):
    return [m.group(0) for line in prose_lines(text) for m in DECIMAL.finditer(line)]


def test_typed_decimals_counted():
    sample = "A margin of 1.5 and 0.9\\,dt, at 0.49\\textwidth; % 3.14 in a comment\n\\input{a1.2.tex}\nv1.2 x"
    assert typed_decimals(sample) == ["1.5", "0.9"]


def test_report_types_few_numbers():
    with open(MAIN) as f:
        found = typed_decimals(f.read())
    assert len(found) <= MAX_TYPED, "paper/main.tex types %d decimal numbers (at most %d): %s" % (
        len(found), MAX_TYPED, ", ".join(found))


def defined_macros():
    names = set()
    for path in MACRO_FILES + [MAIN]:
        if os.path.exists(path):
            with open(path) as f:
                names |= set(re.findall(r"\\(?:re)?newcommand\{?\\([A-Za-z]+)", f.read()))
    return names


def test_every_result_macro_is_defined():
    # The macros the result files define start with these; a report that uses one they do not
    # define fails to build (or prints a stale name).
    prefixes = ("Claim", "Acc", "Abl", "Conv", "Bench", "Realtime", "Swap", "Num", "Ref", "Runs", "Measure", "Region", "Regime")
    with open(MAIN) as f:
        used = set(re.findall(r"\\([A-Za-z]+)", "\n".join(prose_lines(f.read()))))
    missing = sorted(m for m in used if m.startswith(prefixes) and m not in defined_macros())
    assert not missing, "macros used by paper/main.tex and defined nowhere: " + ", ".join(missing)
