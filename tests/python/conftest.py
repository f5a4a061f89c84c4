"""What the Python module's tests share: the paths ctest passes (tests/python/CMakeLists.txt), and the tools."""

import csv
import os
import subprocess

import pytest


def env_path(name):
    value = os.environ.get(name)
    if not value:
        pytest.fail(f"{name} is not set: run these tests through ctest (tests/python/CMakeLists.txt)")
    return value


def path_fixture(fixture, variable):
    """The session fixture `fixture`: the path ctest passes in the environment variable `variable`."""
    def path():
        return env_path(variable)
    return pytest.fixture(scope="session", name=fixture)(path)


scenes_dir = path_fixture("scenes_dir", "CONTACTNN_EXAMPLE_SCENES")
histories_dir = path_fixture("histories_dir", "CONTACTNN_EXAMPLE_HISTORIES")
gen_configs = path_fixture("gen_configs", "CONTACTNN_GEN_CONFIGS")
evaluate_net = path_fixture("evaluate_net", "CONTACTNN_EVALUATE_NET")
source_dir = path_fixture("source_dir", "CONTACTNN_SOURCE_DIR")


def run_tool(args):
    """Runs a tool; fails the test with its output when it does not exit 0."""
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        pytest.fail(f"{' '.join(args)} exited {r.returncode}:\n{r.stdout}\n{r.stderr}")
    return r


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))
