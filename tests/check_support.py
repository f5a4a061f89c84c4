"""What the Python checks under tests/ share: failures gathered and printed as they come, commands that must
succeed, and the exit status at the end (0 all passed, 1 a failure).

  sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
  from check_support import Failures, run_or_exit, required_options
"""
import argparse
import os
import shutil
import subprocess


class Failures(list):
    """The failures of one check script, each printed "FAIL: ..." when it comes (the first `shown` of them; None:
    all)."""

    def __init__(self, shown=None):
        super().__init__()
        self.shown = shown

    def fail(self, message):
        self.append(message)
        if self.shown is None or len(self) <= self.shown:
            print("FAIL: " + message)

    def check(self, condition, message):
        if not condition:
            self.fail(message)

    def exit_status(self, passed, failed=None):
        """Prints `passed`, or `failed` (default "N failures") when anything failed; returns the exit status."""
        if self:
            print(failed or f"{len(self)} failures")
            return 1
        print(passed)
        return 0


def run_or_exit(command, **kwargs):
    """Runs `command` with its output captured; a non-zero exit ends the script with both outputs."""
    p = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if p.returncode != 0:
        raise SystemExit(f"FAIL: {' '.join(command)} exited {p.returncode}:\n{p.stdout}\n{p.stderr}")
    return p


def required_options(*names):
    """The command line of a check whose options are all required (`names`, e.g. "--work"), parsed: the value of
    "--make-scene" is .make_scene."""
    parser = argparse.ArgumentParser()
    for name in names:
        parser.add_argument(name, required=True)
    return parser.parse_args()


def add_consumer_options(parser):
    """The options build_consumer reads (CMake gives them: tests/capi/CMakeLists.txt, tests/examples/), and
    --source-dir and --valgrind, which every such check takes too."""
    for name in ("--cmake", "--generator", "--prefix", "--work", "--source-dir"):
        parser.add_argument(name, required=True)
    parser.add_argument("--valgrind", default="")
    parser.add_argument("--set", action="append", default=[])


def build_consumer(args, project, configure_extra=(), build_extra=()):
    """A fresh build of the consumer project `project` in args.work/build, against the installed package at
    args.prefix alone (CMAKE_PREFIX_PATH, no package registry), args.set as more -D settings: what an FE code's
    build sees (args: cmake, generator, prefix, work, set). A failing step ends the script. Returns the build
    directory and the build's output."""
    if os.path.exists(args.work):
        shutil.rmtree(args.work)
    build = os.path.join(args.work, "build")
    configure = [args.cmake, "-S", project, "-B", build, "-G", args.generator,
                 f"-DCMAKE_PREFIX_PATH={os.path.abspath(args.prefix)}", "-DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF"]
    configure += list(configure_extra) + [f"-D{s}" for s in args.set]
    run_or_exit(configure)
    return build, run_or_exit([args.cmake, "--build", build, *build_extra]).stdout
