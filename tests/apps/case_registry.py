"""The registry of cases the app-level checks of tests/apps share (bad_inputs.py, script_options.py,
hostile_tools.py): a case is a function registered by name, run in a fresh work folder of its own; it passes when
it returns and fails by raising Failure with what went wrong.
"""
import os
import shutil
import sys


class Failure(Exception):
    """A case's check failed: the message says what and why."""


class Cases(dict):
    """name -> (function, needs): needs names what the case runs (bad_inputs.py's tools), () when nothing."""

    def case(self, name, needs=()):
        def register(function):
            self[name] = (function, tuple(needs))
            return function
        return register

    def run(self, names, work, make_context):
        """Runs the cases `names`, each in the emptied folder WORK/NAME with make_context(folder): "PASS NAME"
        or "FAIL NAME" and the reason for each. Returns the exit status: 0 all passed, 1 one failed, 2 an
        unknown case."""
        failed = 0
        for name in names:
            if name not in self:
                print(f"unknown case {name}", file=sys.stderr)
                return 2
            directory = os.path.abspath(os.path.join(work, name))
            shutil.rmtree(directory, ignore_errors=True)
            os.makedirs(directory)
            try:
                self[name][0](make_context(directory))
                print(f"PASS {name}")
            except Failure as e:
                failed += 1
                print(f"FAIL {name}\n{e}")
        return 1 if failed else 0
