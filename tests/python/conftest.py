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


@pytest.fixture(scope="session")
def scenes_dir():
    return env_path("CONTACTNN_EXAMPLE_SCENES")


@pytest.fixture(scope="session")
def histories_dir():
    return env_path("CONTACTNN_EXAMPLE_HISTORIES")


@pytest.fixture(scope="session")
def gen_configs():
    return env_path("CONTACTNN_GEN_CONFIGS")


@pytest.fixture(scope="session")
def evaluate_net():
    return env_path("CONTACTNN_EVALUATE_NET")


@pytest.fixture(scope="session")
def source_dir():
    return env_path("CONTACTNN_SOURCE_DIR")


def run_tool(args):
    """Runs a tool; fails the test with its output when it does not exit 0."""
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        pytest.fail(f"{' '.join(args)} exited {r.returncode}:\n{r.stdout}\n{r.stderr}")
    return r


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))
