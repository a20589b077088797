"""The Python module's tests (ctest python:pytest): PYTHONPATH has build/python, HARNESS_BIN is
the program built beside it."""
import os
import shutil

import pytest


@pytest.fixture(scope="session")
def harness_bin():
    path = os.environ.get("HARNESS_BIN") or shutil.which("harness")
    if not path:
        pytest.fail("HARNESS_BIN is not set (ctest sets it to build/bin/harness)")
    return path


@pytest.fixture(scope="session")
def small():
    """sphere_collision made small and quick: two 2-subdivision spheres, voxel_exact with the
    penalty rule, no references during runs. They touch from about step 1900."""
    import harness
    return harness.Scene.load("sphere_collision").with_(**{
        "bodies.0.shape.subdivisions": 2, "bodies.1.shape.subdivisions": 2,
        "contacts.0.detector": "voxel_exact", "contacts.0.force": {"stiffness": 500},
        "references.solvers": [], "output.frames_every": 0})
