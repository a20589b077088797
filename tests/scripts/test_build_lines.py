"""Builds that must not use CUDA say so. On a machine with a CUDA toolkit (nvcc under
/usr/local/cuda) HARNESS_CUDA=auto turns the backend on, and a special build's instrumentation
flags reach nvcc's host compiler (`-fsanitize=fuzzer-no-link`: gcc rejects it, nothing is fuzzed).
Every CMake configure line in scripts/*.sh and every configure preset states the backend it wants:
HARNESS_CUDA=off for the sanitizer and fuzz builds, on for the device check, and the release and
debug presets leave it to auto. A configure line this table does not know fails, so a new special
build must say what it wants."""

import json
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# script (or preset) -> the HARNESS_CUDA it must configure with (None: not given, i.e. auto)
SCRIPTS = {"scripts/fuzz.sh": "off", "scripts/device_check.sh": "on"}
PRESETS = {"release": None, "debug": None, "asan": "off"}


def configure_lines(text):
    """The CMake configure commands of a shell script (continuation lines joined), not `cmake --build`
    nor `cmake --preset` (the presets are checked apart)."""
    joined = re.sub(r"\\\n\s*", " ", text)
    return [l for l in joined.splitlines()
            if re.search(r"(^|\s)cmake\s+(.*\s)?-[SBD]", l) and not re.search(r"cmake\s+--(build|preset)\b", l)
            and not l.lstrip().startswith("#")]


def cuda_value(line):
    m = re.search(r"-DHARNESS_CUDA(?::\w+)?=(\w+)", line)
    return m.group(1) if m else None


def script_problems(name, text):
    problems = []
    for line in configure_lines(text):
        want = SCRIPTS.get(name, "?")
        got = cuda_value(line)
        if want == "?":
            problems.append("%s configures a build this test does not know: %s" % (name, line.strip()))
        elif got != want:
            problems.append("%s: HARNESS_CUDA=%s, expected %s: %s" % (name, got, want, line.strip()))
    return problems


def test_every_configure_line_says_its_cuda_backend():
    problems, seen = [], set()
    for f in sorted(os.listdir(os.path.join(ROOT, "scripts"))):
        if f.endswith(".sh"):
            name = "scripts/" + f
            text = open(os.path.join(ROOT, name)).read()
            if configure_lines(text):
                seen.add(name)
            problems += script_problems(name, text)
    assert not problems, problems
    assert seen == set(SCRIPTS), seen


def test_presets_say_their_cuda_backend():
    presets = json.load(open(os.path.join(ROOT, "CMakePresets.json")))["configurePresets"]
    got = {p["name"]: p.get("cacheVariables", {}).get("HARNESS_CUDA") for p in presets}
    assert got == PRESETS


def test_the_check_fails_without_the_flag():
    text = open(os.path.join(ROOT, "scripts", "fuzz.sh")).read()
    assert not script_problems("scripts/fuzz.sh", text)
    stripped = text.replace("-DHARNESS_CUDA=off", "")
    assert script_problems("scripts/fuzz.sh", stripped), "fuzz.sh without HARNESS_CUDA=off passes the check"
    assert script_problems("scripts/new_build.sh", "cmake -S . -B build-x -DHARNESS_SANITIZE=ON\n")
