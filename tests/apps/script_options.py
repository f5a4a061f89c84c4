#!/usr/bin/env python3
"""The scripts check every option before any work (scripts/script_checks.py): a value out of range, a missing
input or an output that cannot be written is exit status 2 with a message naming the option, at once, with no
Python traceback and nothing written; a contact pair without slave nodes stops scene-study before any training.

Every case runs scripts in a fresh directory and checks the exit status, stderr (a regular expression), the
absence of "Traceback", and that no output appeared where none may.

Usage: script_options.py --source-dir DIR --build DIR --work DIR (--list | --case NAME | --all)
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from case_registry import Cases, Failure  # noqa: E402  (tests/apps/case_registry.py)

CASES = Cases()
case = CASES.case


class Context:
    def __init__(self, source, build, directory):
        self.source = source
        self.build = build
        self.dir = directory

    def path(self, name):
        return os.path.join(self.dir, name)

    def write(self, name, text):
        with open(self.path(name), "w") as f:
            f.write(text)
        return self.path(name)

    def script(self, name):
        return os.path.join(self.source, "scripts", name)

    def run(self, command, env=None, timeout=120):
        started = time.monotonic()
        try:
            p = subprocess.run(command, cwd=self.dir, capture_output=True, text=True, timeout=timeout,
                               env=dict(os.environ, **(env or {})))
        except subprocess.TimeoutExpired:
            raise Failure(f"ran past {timeout} s: {' '.join(command)}")
        return p.returncode, p.stdout, p.stderr, time.monotonic() - started

    def expect(self, command, code, pattern, absent=(), env=None, within=60.0):
        """`command` exits with `code` within `within` seconds, stderr matching `pattern`, no traceback, and none
        of the paths in `absent` exists afterwards."""
        rc, out, err, seconds = self.run(command, env=env)
        report = f"command: {' '.join(command)}\nexit: {rc} after {seconds:.1f} s\nstderr:\n{err[-3000:]}\n" \
                 f"stdout:\n{out[-1500:]}"
        if "Traceback" in err or "Traceback" in out:
            raise Failure(f"a Python traceback\n{report}")
        if rc != code:
            raise Failure(f"exit status {rc}, expected {code}\n{report}")
        if not re.search(pattern, err, re.S):
            raise Failure(f"stderr does not match {pattern!r}\n{report}")
        if seconds > within:
            raise Failure(f"took {seconds:.1f} s, more than {within} s: work before the check?\n{report}")
        for path in absent:
            if os.path.exists(self.path(path)):
                raise Failure(f"{path} exists after the refused run\n{report}")

    def deck(self, name="deck.inp"):
        """Two stacked unit cubes and one contact pair (bottom face of the upper on the top face of the lower)."""
        return self.write(name, "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n"
                                "7, 1, 1, 1\n8, 0, 1, 1\n11, 0, 0, 1.1\n12, 1, 0, 1.1\n13, 1, 1, 1.1\n14, 0, 1, 1.1\n"
                                "15, 0, 0, 2.1\n16, 1, 0, 2.1\n17, 1, 1, 2.1\n18, 0, 1, 2.1\n"
                                "*ELEMENT, TYPE=C3D8, ELSET=LOWER\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
                                "*ELEMENT, TYPE=C3D8, ELSET=UPPER\n2, 11, 12, 13, 14, 15, 16, 17, 18\n"
                                "*SURFACE, NAME=TOP\nLOWER, S2\n*SURFACE, NAME=BOTTOM\nUPPER, S1\n"
                                "*CONTACT PAIR, INTERACTION=I\nBOTTOM, TOP\n")


@case("scene_study_options")
def _(ctx):
    # --target -1 was accepted: every size and the long round were trained for a target nothing can meet.
    deck = ctx.deck()
    base = [sys.executable, ctx.script("scene-study"), "--scene", deck, "--surface", "bilinear", "--output", "out",
            "--build-dir", ctx.build]
    for extra, says in ((["--target", "-1"], r"argument --target: must be a finite number > 0, got -1"),
                        (["--target", "0"], r"argument --target: must be a finite number > 0, got 0"),
                        (["--target", "nan"], r"argument --target: must be a finite number > 0, got nan"),
                        (["--margin", "0"], r"argument --margin: must be a finite number > 0"),
                        (["--sizes", "8,0"], r"argument --sizes: '8,0': must be an integer in 1\.\.4096, got 0"),
                        (["--sizes", "8,,16"], r"argument --sizes: expected integers separated by ','"),
                        (["--epochs", "0"], r"argument --epochs: must be an integer in 1\.\.100000000, got 0"),
                        (["--long-epochs", "-5"], r"argument --long-epochs: must be an integer in 0\.\."),
                        (["--threads", "5000"], r"argument --threads: must be an integer in 0\.\.1024, got 5000"),
                        (["--seed", "-1"], r"argument --seed: must be an integer in 0\.\."),
                        (["--pair", "-1"], r"argument --pair: must be an integer in 0\.\.1000000, got -1"),
                        (["--count", "99"], r"argument --count: must be an integer in 100\.\."),
                        (["--deformation", "0.5"], r"argument --deformation: must be a finite number >= 0 and <= 0\.49"),
                        (["--boundary-fraction", "2"], r"argument --boundary-fraction: must be a finite number"),
                        (["--capture", "0"], r"argument --capture: must be a finite number > 0"),
                        (["--normal-tilt-tangent", "-1"], r"argument --normal-tilt-tangent: must be a finite number >= 0"),
                        (["--input-quantile", "0.5"], r"argument --input-quantile: must be a finite number >= 0 and "
                                                      r"<= 0\.49")):
        ctx.expect(base + extra, 2, says, absent=["out"], within=10)
    ctx.expect(base[:3] + ["missing.inp"] + base[4:], 2, r"--scene 'missing\.inp': no such file", absent=["out"],
               within=10)


@case("scene_study_pair_without_slave_nodes")
def _(ctx):
    # A pair with no slave nodes trained for 32 s before failing: it stops after the pairs, before any training.
    # Here every slave node is also a master node (SPEC 7 leaves those out).
    deck = ctx.write("shared.inp", "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n"
                                   "7, 1, 1, 1\n8, 0, 1, 1\n*ELEMENT, TYPE=C3D8, ELSET=LOWER\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
                                   "*SURFACE, NAME=TOP\nLOWER, S2\n*SURFACE, NAME=SN, TYPE=NODE\n5, 6, 7, 8\n"
                                   "*CONTACT PAIR, INTERACTION=I\nSN, TOP\n")
    ctx.expect([sys.executable, ctx.script("scene-study"), "--scene", deck, "--surface", "bilinear", "--output",
                "out", "--build-dir", ctx.build], 1, r"scene-study: pair 0 of .*shared\.inp has no slave nodes: "
                                                     r"nothing to study", absent=["out/train.h5", "out/scene-8.h5"],
               within=15)


@case("scene_table_options")
def _(ctx):
    # --max-pairs -1 printed an empty table and exited 0.
    deck = ctx.deck()
    base = [sys.executable, ctx.script("scene-table"), "--output", "out", "--build-dir", ctx.build, deck]
    ctx.expect(base + ["--max-pairs", "-1"], 2, r"argument --max-pairs: must be an integer in 1\.\.", absent=["out"],
               within=10)
    ctx.expect(base + ["--max-pairs", "0"], 2, r"argument --max-pairs: must be an integer in 1\.\.", absent=["out"],
               within=10)
    ctx.expect(base + ["--surfaces", "bilinear,quadratic"], 2, r"argument --surfaces: expected one or more of "
                                                               r"bilinear, gregory", absent=["out"], within=10)
    ctx.expect(base + ["--threads", "-2"], 2, r"argument --threads: must be an integer in 0\.\.1024", absent=["out"],
               within=10)
    ctx.expect(base + ["missing.inp"], 2, r"deck 'missing\.inp': no such file", absent=["out"], within=10)
    # The options for scene-study after "--" are checked (scene-study --check) before any study runs.
    ctx.expect(base + ["--", "--target", "-1"], 2, r"argument --target: must be a finite number > 0, got -1.*"
                                                   r"scene-study options after '--'",
               absent=["out/deck-0-bilinear/pairs.csv", "out/scene-table.md"], within=20)


@case("outputs_that_cannot_be_written")
def _(ctx):
    # A read-only output gave Python tracebacks. Here the output lies under a regular file (which fails for root
    # too): each script names the option and exits 2 before any work.
    deck = ctx.deck()
    ctx.write("file", "a file, not a directory\n")
    os.makedirs(ctx.path("scenes"))
    shutil.copy(deck, ctx.path("scenes/deck.inp"))
    weights = os.path.join(ctx.source, "data", "weights", "bilinear-8.h5")
    py = sys.executable
    runs = [
        ([py, ctx.script("scene-study"), "--scene", deck, "--surface", "bilinear", "--output", "file/out",
          "--build-dir", ctx.build], r"--output '.*file/out': cannot write there"),
        ([py, ctx.script("scene-table"), "--output", "file/out", "--build-dir", ctx.build, deck],
         r"--output 'file/out': cannot write there"),
        ([py, ctx.script("node-orders"), "--scene", deck, "--surface", "bilinear", "--weights", weights, "--work",
          "file/out", "--build-dir", ctx.build], r"--work 'file/out': cannot write there"),
        ([py, ctx.script("memory-check"), "--build", ctx.build, "--work", "file/out", "--rows", "10"],
         r"--work '.*file/out': cannot write there"),
        ([py, ctx.script("kill-test"), "--build", ctx.build, "--work", "file/out", "--short"],
         r"--work '.*file/out': cannot write there"),
        (["bash", ctx.script("run-study"), "--no-build", "--build-dir", ctx.build, "--data", "d/data.h5",
          "--network", "n/net.h5", "--report", "file/out/report"], r"run-study: --report: cannot write in '.*file/out'"),
    ]
    if os.access(os.path.join(ctx.build, "tests", "contact", "scene-check"), os.X_OK):
        runs.append(([py, ctx.script("validate-scenes"), "--build", ctx.build, "--scenes", "scenes", "--work",
                      "file/out"], r"--work 'file/out': cannot write there"))
    for command, says in runs:
        ctx.expect(command, 2, says, within=20)


@case("results_pages")
def _(ctx):
    # The scripts that write a results page (--page) check it before any work: a page under a regular file, or a
    # page that is a directory, is exit 2 naming --page, and nothing is built, run or written.
    deck = ctx.deck()
    ctx.write("file", "a file, not a directory\n")
    os.makedirs(ctx.path("folder"))
    py = sys.executable
    commands = {
        "frontier": ([py, ctx.script("frontier"), "--build-dir", ctx.build, "--work", "w", "--output", "o"],
                     ["w", "o"]),
        "bench-search": (["bash", ctx.script("bench-search"), "--build", ctx.build], []),
        "bench-against": ([py, ctx.script("bench-against"), "HEAD", "--build", ctx.build], []),
        "bench-cgal": ([py, ctx.script("bench-cgal"), "--build", ctx.build], []),
        "scene-table": ([py, ctx.script("scene-table"), "--output", "o", "--build-dir", ctx.build, deck], ["o"]),
    }
    for name, (command, absent) in commands.items():
        ctx.expect(command + ["--page", "file/page.md"], 2, r"--page 'file/page\.md': cannot write there",
                   absent=absent, within=20)
        ctx.expect(command + ["--page", "folder"], 2, r"--page 'folder' is a directory, not a file", absent=absent,
                   within=20)
    for name in ("frontier", "bench-search", "bench-cgal"):
        command, absent = commands[name]
        ctx.expect(command + ["--page", "page.md", "--no-page"], 2, r"--page and --no-page exclude each other",
                   absent=absent + ["page.md"], within=20)


@case("other_script_options")
def _(ctx):
    deck = ctx.deck()
    weights = os.path.join(ctx.source, "data", "weights", "bilinear-8.h5")
    py = sys.executable
    runs = [
        ([py, ctx.script("node-orders"), "--scene", deck, "--pair", "-1", "--surface", "bilinear", "--weights",
          weights, "--work", "w"], r"argument --pair: must be an integer in 0\.\.", ["w"]),
        ([py, ctx.script("node-orders"), "--scene", deck, "--surface", "bilinear", "--weights", "none.h5", "--work",
          "w", "--build-dir", ctx.build], r"--weights 'none\.h5': no such file", ["w"]),
        ([py, ctx.script("memory-check"), "--build", ctx.build, "--work", "w", "--rows", "0"],
         r"argument --rows: must be an integer in 1\.\.", ["w"]),
        ([py, ctx.script("memory-check"), "--build", ctx.build, "--work", "w", "--limit-mb", "-5"],
         r"argument --limit-mb: must be a finite number > 0", ["w"]),
        ([py, ctx.script("memory-check"), "--build", ctx.build, "--work", "w", "--reference", "no-such-build"],
         r"no-such-build/apps/gen-configs/gen-configs not found", ["w"]),
        ([py, ctx.script("kill-test"), "--build", ctx.build, "--work", "w", "--rounds", "0"],
         r"argument --rounds: must be an integer in 1\.\.", ["w"]),
        (["bash", ctx.script("run-study"), "--no-build", "--build-dir", ctx.build, "--jobs", "0", "--report", "r"],
         r"run-study: --jobs must be an integer in 1\.\.4096, got '0'", ["r"]),
        (["bash", ctx.script("run-study"), "--no-build", "--build-dir", ctx.build, "--threads", "2000", "--report",
          "r"], r"run-study: --threads must be an integer in 0\.\.1024, got '2000'", ["r"]),
        (["bash", ctx.script("run-study"), "--no-build", "--build-dir", ctx.build, "--threads", "x", "--report", "r"],
         r"run-study: --threads must be an integer", ["r"]),
        (["bash", ctx.script("run-study"), "--no-build", "--build-dir", ctx.build, "--weights", "none.h5", "--data",
          "d/data.h5", "--report", "r"], r"run-study: no network file '.*none\.h5'", ["r", "d"]),
        (["bash", ctx.script("thread-scaling"), "--build", ctx.build, "--work", "w", "--threads", "1,x"],
         r"thread-scaling: --threads wants integers in 1\.\.1024", ["w"]),
        (["bash", ctx.script("thread-scaling"), "--build", ctx.build, "--work", "w", "--threads", "1,2000"],
         r"thread-scaling: --threads wants integers in 1\.\.1024", ["w"]),
        (["bash", ctx.script("thread-scaling"), "--build", "no-such-build", "--work", "w"],
         r"thread-scaling: --build 'no-such-build': no such directory", ["w"]),
        (["bash", ctx.script("thread-scaling"), "--frobnicate"], r"thread-scaling: unknown option '--frobnicate'", ["w"]),
        ([py, ctx.script("bench-against"), "HEAD", "--build", ctx.build, "--rounds", "0"],
         r"argument --rounds: must be an integer in 1\.\.100", []),
        ([py, ctx.script("bench-against"), "HEAD", "--build", ctx.build, "--min-time", "0"],
         r"argument --min-time: must be a finite number > 0", []),
        ([py, ctx.script("bench-cgal"), "--build", ctx.build, "--repeats", "0"],
         r"argument --repeats: must be an integer in 1\.\.100", []),
        ([py, ctx.script("bench-cgal"), "--build", ctx.build, "--faces", "10", "--slaves", "100", "--no-page"],
         r"--slaves 100 at spacing 0\.3 need more than --faces 10", []),
        ([py, ctx.script("bench-cgal"), "--build", "no-such-build", "--no-page"],
         r"no-such-build/bench/bench_cgal not found", []),
        ([py, ctx.script("bench-against"), "no-such-commit", "--build", ctx.build],
         r"'no-such-commit' is not a commit of this repository", []),
    ]
    for command, says, absent in runs:
        ctx.expect(command, 2, says, absent=absent, within=20)


@case("fuzz_arguments")
def _(ctx):
    # Checked before the clang build (a bad count ran libFuzzer with -max_total_time=0: without end).
    env = {"CONTACTNN_FUZZ_BUILD": ctx.path("fuzz-build")}
    for args, says in ((["0"], r"SECONDS_PER_TARGET must be an integer in 1\.\.9999999, got '0'"),
                       (["ten"], r"SECONDS_PER_TARGET must be an integer"),
                       (["5", "toml"], r"unknown target 'toml' \(csv, config\)")):
        ctx.expect(["bash", ctx.script("fuzz")] + args, 2, says, env=env, absent=["fuzz-build"], within=20)
    ctx.expect(["bash", ctx.script("fuzz"), "5"], 2, r"CONTACTNN_FUZZ_JOBS must be an integer in 1\.\.9999, got 'two'",
               env=dict(env, CONTACTNN_FUZZ_JOBS="two"), absent=["fuzz-build"], within=20)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--build", required=True)
    parser.add_argument("--work", default="script-options")
    parser.add_argument("--case", action="append", default=[])
    parser.add_argument("--all", action="store_true")
    parser.add_argument("--list", action="store_true")
    a = parser.parse_args()
    if a.list:
        print(";".join(CASES))
        return 0
    return CASES.run(list(CASES) if a.all else a.case, a.work,
                     lambda directory: Context(os.path.abspath(a.source_dir), os.path.abspath(a.build), directory))


if __name__ == "__main__":
    sys.exit(main())
