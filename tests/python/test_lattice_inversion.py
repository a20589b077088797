"""scripts/lattice_inversion.py: a box lattice's rows out of their starting order (an inverted cell)."""
import importlib.util
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "lattice_inversion.py")
spec = importlib.util.spec_from_file_location("lattice_inversion", SCRIPT)
li = importlib.util.module_from_spec(spec)
spec.loader.exec_module(li)


def lattice():
    """A 2 x 2 x 3 lattice, 1 mm apart."""
    return np.array([[x, y, z] for x in (0.0, 1e-3) for y in (0.0, 1e-3) for z in (0.0, 1e-3, 2e-3)])


def test_an_intact_lattice_has_no_inverted_row():
    x0 = lattice()
    x = x0 * 0.5  # compressed by half, every row still in order
    for axis in range(3):
        rows, bad, deepest, first = li.inverted_rows(x0, x, axis)
        assert bad == 0 and deepest == 0.0 and first is None
    assert li.inverted_rows(x0, x, 2)[0] == 4 and li.inverted_rows(x0, x, 0)[0] == 6


def test_a_top_node_pushed_past_the_one_beneath_is_found():
    x0 = lattice()
    x = x0.copy()
    top = int(np.argmax((x0[:, 0] == 1e-3) & (x0[:, 1] == 0.0) & (x0[:, 2] == 2e-3)))
    x[top, 2] = 0.7e-3  # 0.3 mm below the node it sat above
    rows, bad, deepest, first = li.inverted_rows(x0, x, 2)
    assert (rows, bad) == (4, 1)
    assert abs(deepest - 0.3e-3) < 1e-12
    assert first == ("(1, 0)", 1)
    assert li.inverted_rows(x0, x, 0)[1] == 0  # along x the rows keep their order


def test_bad_input_exits_2_naming_the_key():
    env = dict(os.environ)
    p = subprocess.run([sys.executable, SCRIPT, "cylinder_press", "--set", "contacts.0.nope=1"], capture_output=True,
                       text=True, env=env)
    assert p.returncode == 2 and "contacts.0.nope" in p.stderr and p.stderr.count("\n") == 1
