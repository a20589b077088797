"""The map (docs/architecture.md) and the README stay short and true to the tree: their lengths,
every repository path they name in backticks, the identifiers they attribute to a file, every
relative link of the documentation pages, the README's tour commands, and the map's include
rule (no FCL, libccd, CGAL or Bullet header, and nothing of reference/, experiments/ or python/,
under core/). A renamed or removed file fails here until the page that names it follows.

Run by ctest (scripts:pytest) or: /usr/bin/python3 -m pytest -q tests/scripts/test_docs_map.py"""

import glob
import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MAP = "docs/architecture.md"
README = "README.md"
MAX_LINES = {MAP: 300, README: 150}

# Pages the documentation links to that other work writes: docs/outputs.md (`harness outputs >
# docs/outputs.md`) and results/SUMMARY.md. A link to one is checked as soon as it exists; until
# then it is let through. Take a name out of this set once its file is committed.
PENDING = set()

# A backticked token is a repository path when its first component is one of these folders (a
# fixed list, so that renaming a folder fails too), or when it is a bare file name with one of
# SOURCE_EXT (then some file of that name must exist). Output file names (steps.csv,
# summary.json, ...) name a run's files, not the repository's, and are not checked.
TOP = {"core", "reference", "experiments", "python", "scripts", "tests", "results", "paper", "docs", "cmake"}
SOURCE_EXT = (".py", ".cpp", ".hpp", ".md", ".sh", ".cu", ".cuh", ".inl", ".tex")
# Paths that do not live in the repository: build outputs, the runs' cache, placeholders.
IGNORED = (re.compile(r"^build[-/]|^/|^results/sweeps|^DIR/|^OUT/|SCENE|<|>|\.\.\.|\bNAME\b|\bFILE\b"))


def read(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8") as f:
        return f.read()


def prose(text):
    """The text outside fenced code blocks."""
    return re.sub(r"^```.*?^```[^\n]*$", "", text, flags=re.M | re.S)


def backticked(text):
    return re.findall(r"`([^`\n]+)`", prose(text))


def expand(path):
    """core/run/summary.{hpp,cpp} -> core/run/summary.hpp, core/run/summary.cpp."""
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    return [p for alt in m.group(1).split(",") for p in expand(path[:m.start()] + alt + path[m.end():])]


def repository_paths(text):
    """The backticked tokens of `text` that name repository paths (see TOP and SOURCE_EXT)."""
    out = []
    for tok in backticked(text):
        if re.search(r"\s", tok) or IGNORED.search(tok) or tok.startswith("-"):
            continue
        if "/" in tok:
            if tok.split("/")[0] in TOP:
                out.append(tok)
        elif tok.endswith(SOURCE_EXT) and re.fullmatch(r"[\w.\-*]+", tok):
            out.append(tok)
    return out


def all_files():
    names = set()
    for d, dirs, files in os.walk(ROOT):
        dirs[:] = [x for x in dirs if not x.startswith(".") and not x.startswith("build")]
        names.update(files)
    return names


def missing_paths(rel):
    text = read(rel)
    names = None
    missing = []
    for tok in repository_paths(text):
        for p in expand(tok):
            if "/" not in p:
                names = names if names is not None else all_files()
                if p not in names:
                    missing.append(tok)
            elif "*" in p:
                if not glob.glob(os.path.join(ROOT, p)):
                    missing.append(tok)
            elif not os.path.exists(os.path.join(ROOT, p)):
                missing.append(tok)
    return sorted(set(missing))


@pytest.mark.parametrize("rel", [MAP, README])
def test_short(rel):
    n = len(read(rel).splitlines())
    assert n <= MAX_LINES[rel], "%s has %d lines; at most %d (details go to docs/usage.md, docs/findings.md)" % (
        rel, n, MAX_LINES[rel])


@pytest.mark.parametrize("rel", [MAP, README])
def test_named_paths_exist(rel):
    assert repository_paths(read(rel)), "no repository path found in %s: the extraction is broken" % rel
    missing = missing_paths(rel)
    assert not missing, "%s names paths that do not exist: %s" % (rel, ", ".join(missing))


# `name` (`path`): an identifier the page attributes to a file.
PAIR = re.compile(r"`([A-Za-z_][\w:]*)(?:\(\))?`\s+\(`([\w./\-]+)`")


def named_identifiers(text):
    return PAIR.findall(prose(text))


@pytest.mark.parametrize("rel", [MAP, README])
def test_identifiers_in_their_files(rel):
    wrong = []
    for name, path in named_identifiers(read(rel)):
        full = os.path.join(ROOT, path)
        if not os.path.isfile(full):
            wrong.append("%s (%s: no such file)" % (name, path))
            continue
        with open(full, encoding="utf-8") as f:
            src = f.read()
        parts = [p for p in re.split(r"::|\.", name) if p]
        if not all(re.search(r"\b%s\b" % re.escape(p), src) for p in parts):
            wrong.append("%s (not in %s)" % (name, path))
    assert not wrong, "%s attributes identifiers to files that do not hold them: %s" % (rel, "; ".join(wrong))


def test_map_names_identifiers():
    # The check above is vacuous if the pattern stops matching the map's style.
    assert len(named_identifiers(read(MAP))) >= 10


def doc_pages():
    return [README] + sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "docs", "*.md")))


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def slug(heading):
    """GitHub's anchor of a heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(path):
    with open(path, encoding="utf-8") as f:
        text = prose(f.read())
    return {slug(m) for m in re.findall(r"^#{1,6}\s+(.*?)\s*#*$", text, flags=re.M)}


@pytest.mark.parametrize("rel", doc_pages())
def test_relative_links_exist(rel):
    here = os.path.dirname(os.path.join(ROOT, rel))
    broken = []
    for target in LINK.findall(prose(read(rel))):
        if re.match(r"^[a-z][a-z0-9+.\-]*:", target):  # https:, mailto:
            continue
        path, _, frag = target.partition("#")
        full = os.path.normpath(os.path.join(here, path)) if path else os.path.join(ROOT, rel)
        if path and not os.path.exists(full):
            if os.path.relpath(full, ROOT) in PENDING:
                continue
            broken.append(target)
        elif frag and full.endswith(".md") and frag not in anchors(full):
            broken.append(target + " (no such heading)")
    assert not broken, "%s links to what does not exist: %s" % (rel, ", ".join(broken))


def test_readme_tour_commands():
    """The README's commands run bundled scenes and compare with committed references."""
    blocks = "\n".join(re.findall(r"^```sh\n(.*?)^```", read(README), flags=re.M | re.S)).replace("\\\n", " ")
    runs = re.findall(r"harness run (\S+)", blocks)
    compares = re.findall(r"--compare (\S+)", blocks)
    assert runs and compares
    for scene in runs:
        assert os.path.isfile(os.path.join(ROOT, "experiments", "scenes", scene + ".json")), scene
    for ref in compares:
        assert os.path.isfile(os.path.join(ROOT, ref, "summary.json")), ref
    for script in re.findall(r"^(scripts/\S+)", blocks, flags=re.M):
        assert os.path.isfile(os.path.join(ROOT, script)), script


FOREIGN = re.compile(r'#\s*include\s*(<(fcl|ccd|CGAL|Bullet\w*|LinearMath)/|<bt\w*\.h>|"(reference|experiments|python)/)')


def test_core_includes_no_reference_library():
    """What the map says of core/: no FCL, libccd, CGAL or Bullet, nothing of the programs."""
    bad = []
    for path in glob.glob(os.path.join(ROOT, "core", "**", "*"), recursive=True):
        if os.path.isfile(path) and path.endswith((".hpp", ".cpp", ".cu", ".cuh", ".inl", ".h")):
            with open(path, encoding="utf-8") as f:
                for n, line in enumerate(f, 1):
                    if FOREIGN.search(line):
                        bad.append("%s:%d: %s" % (os.path.relpath(path, ROOT), n, line.strip()))
    assert not bad, "core/ includes what only reference/ may:\n" + "\n".join(bad)
