"""The repository stays a repository (results/README.md, "What is committed"): the tracked tree
under 50 MiB, and no tracked file over 5 MB stored uncompressed. Counted over `git ls-files` (the
files as checked out); skipped outside a git checkout."""

import os
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TREE_LIMIT = 50 * 2 ** 20      # bytes: the GPU machine takes at most 64 MiB of working tree
FILE_LIMIT = 5 * 10 ** 6       # bytes: a larger file is committed compressed
COMPRESSED = (".gz", ".xz", ".bz2", ".zip", ".png", ".pdf")


def tracked(root=ROOT):
    """{path: bytes} of the tracked files present in the work tree."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    files = {}
    for rel in out.decode().split("\0"):
        p = os.path.join(root, rel)
        if rel and os.path.isfile(p) and not os.path.islink(p):
            files[rel] = os.path.getsize(p)
    return files


def oversized(files):
    return sorted(f for f, n in files.items() if n > FILE_LIMIT and not f.endswith(COMPRESSED))


def test_the_tracked_tree_is_under_50_mib():
    files = tracked()
    total = sum(files.values())
    biggest = sorted(files.items(), key=lambda kv: -kv[1])[:5]
    assert total < TREE_LIMIT, "tracked tree %.1f MiB (limit 50): largest %s" % (
        total / 2 ** 20, ", ".join("%s %.1f MB" % (f, n / 1e6) for f, n in biggest))


def test_no_large_file_is_committed_uncompressed():
    bad = oversized(tracked())
    assert not bad, "over 5 MB and not compressed (store it as .csv.gz: scripts/store_results.py): %s" % bad


def test_the_checks_fail_on_a_large_plain_file(tmp_path):
    # The rule itself: a 6 MB plain CSV is caught, its gzipped form is not.
    assert oversized({"results/x/steps.csv": 6 * 10 ** 6, "results/x/steps.csv.gz": 6 * 10 ** 6}) == ["results/x/steps.csv"]
    # and on a real checkout: a git repository with one such file added
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    (tmp_path / "big.csv").write_bytes(b"0," * (3 * 10 ** 6))
    subprocess.run(["git", "-C", str(tmp_path), "add", "big.csv"], check=True)
    assert oversized(tracked(str(tmp_path))) == ["big.csv"]
