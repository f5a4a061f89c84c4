"""examples/python/contact_search.py: it runs (a Gmsh file written and read back with meshio, ten increments), and
its answers are the plate's: every slave node of the block's underside finds the flat top z = 0 of the plate
straight below it, with the gap its height."""

import importlib.util
import os
import subprocess
import sys

import numpy as np

import contactnn  # noqa: F401  (the module must import before the example does)


def example_path():
    return os.path.join(os.environ["CONTACTNN_SOURCE_DIR"], "examples", "python", "contact_search.py")


def load_example():
    spec = importlib.util.spec_from_file_location("contact_search_example", example_path())
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_example_answers(tmp_path):
    slaves, history = load_example().run(str(tmp_path), verbose=False)
    assert len(history) == 10 and len(slaves) == 49
    penetrating = 0
    for x, contacts in history:
        s = x[slaves]
        assert np.all(contacts.status == 0)
        np.testing.assert_allclose(contacts.gap, s[:, 2], rtol=0, atol=1e-12)
        np.testing.assert_allclose(contacts.point[:, :2], s[:, :2], rtol=0, atol=1e-12)
        np.testing.assert_allclose(contacts.point[:, 2], 0.0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(contacts.normal, np.tile([0.0, 0.0, 1.0], (len(s), 1)), rtol=0, atol=1e-12)
        penetrating += int(np.sum(contacts.gap < 0))
    assert penetrating > 0, "the example should press the block into the plate"


def test_example_runs_as_a_script(tmp_path):
    r = subprocess.run([sys.executable, example_path(), "--output", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    table = [line for line in r.stdout.splitlines() if line.split() and line.split()[0].isdigit()]
    assert len(table) == 10 and all(line.split()[1] == "49" for line in table), r.stdout
    assert (tmp_path / "two-bodies.msh").exists()
