#!/usr/bin/env python3
"""The tools on the cases of issue 39's hostile run: outputs that cannot be written or that are or hold an input,
for every tool and every output option (io::require_outputs), and the doubtful cases of the tools' command lines
and histories. Each case runs in a fresh directory on a small deck and .frd written by scripts/make-large-history
(the project's own; no CalculiX needed) and checks:

  - the documented exit code (docs/tools.md: 2 bad command line, 3 bad input data, 4 I/O failure; never 1);
  - a message on stderr naming the option and the path (a regular expression per case);
  - for a refused run, nothing written: every file of the directory (inputs included) unchanged, nothing added.

Usage: hostile_tools.py --gen-configs P --train-net P --evaluate-net P --replay P --scene-study P
                        --source-dir DIR --work DIR (--list | --case NAME)
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

CASES = {}


def case(name):
    def register(function):
        CASES[name] = function
        return function
    return register


class Failure(Exception):
    pass


def snapshot(directory):
    """Every file under `directory` with its size, modification time and content."""
    state = {}
    for root, dirs, files in os.walk(directory):
        for name in dirs + files:
            path = os.path.join(root, name)
            rel = os.path.relpath(path, directory)
            if os.path.isfile(path):
                with open(path, "rb") as f:
                    state[rel] = (os.stat(path).st_mtime_ns, f.read())
            else:
                state[rel] = None
    return state


class Context:
    def __init__(self, args, directory):
        self.a = args
        self.dir = directory

    def path(self, *names):
        return os.path.join(self.dir, *names)

    def history(self, where="."):
        """deck.inp and run.frd (a small synthetic history) in `where` under the case's directory."""
        out = self.path(where)
        tmp = self.path(".make-history")
        subprocess.run([sys.executable, os.path.join(self.a.source_dir, "scripts", "make-large-history"), "--output",
                        tmp, "--slaves", "60", "--faces", "24", "--increments", "2"], check=True,
                       capture_output=True)
        os.makedirs(out, exist_ok=True)
        shutil.move(os.path.join(tmp, "large.inp"), os.path.join(out, "deck.inp"))
        shutil.move(os.path.join(tmp, "large.frd"), os.path.join(out, "run.frd"))
        shutil.rmtree(tmp)
        return os.path.join(out, "deck.inp"), os.path.join(out, "run.frd")

    def run(self, tool, args, timeout=120):
        r = subprocess.run([getattr(self.a, tool.replace("-", "_"))] + args, cwd=self.dir, capture_output=True,
                           text=True, errors="replace", timeout=timeout)
        if r.returncode < 0:
            raise Failure(f"{tool} {args}: killed by signal {-r.returncode}\n{r.stderr}")
        return r

    def refused(self, tool, args, code, pattern):
        """The run exits `code` with `pattern` on stderr and changes nothing in the case's directory."""
        before = snapshot(self.dir)
        r = self.run(tool, args)
        if r.returncode != code:
            raise Failure(f"{tool} {' '.join(args)}: exit {r.returncode}, expected {code}\n{r.stdout}{r.stderr}")
        if not re.search(pattern, r.stderr):
            raise Failure(f"{tool} {' '.join(args)}: stderr does not match {pattern!r}:\n{r.stderr}")
        if "internal" in r.stderr or "terminate called" in r.stderr:
            raise Failure(f"{tool}: an internal error:\n{r.stderr}")
        after = snapshot(self.dir)
        if before != after:
            changed = sorted(set(before) ^ set(after)) or sorted(k for k in before if before[k] != after.get(k))
            raise Failure(f"{tool} {' '.join(args)}: the directory changed: {changed}")
        return r


REPLAY = ["--repeats", "1", "--quiet"]


# ---- Failure 5 and 6: outputs that cannot be written (exit 4), outputs that are or hold an input (exit 2) ----

@case("replay_report_under_proc")
def _(ctx):
    deck, frd = ctx.history()
    ctx.refused("replay", ["--scene", deck, "--results", frd, "--report", "/proc/x/y"] + REPLAY, 4,
                r"--report '/proc/x/y': cannot write")


@case("replay_report_dev_null")
def _(ctx):
    deck, frd = ctx.history()
    ctx.refused("replay", ["--scene", deck, "--results", frd, "--report", "/dev/null"] + REPLAY, 4,
                r"--report '/dev/null': .*not a directory")


@case("replay_report_is_the_deck")
def _(ctx):
    deck, frd = ctx.history()
    ctx.refused("replay", ["--scene", deck, "--results", frd, "--report", deck] + REPLAY, 2,
                r"--report '.*deck.inp' and --scene '.*deck.inp' are the same file")


@case("replay_report_holds_the_inputs")
def _(ctx):
    # docs/robustness.md: a report directory holding an input is refused before anything is written; the
    # report was written beside the deck and the .frd, exit 0.
    deck, frd = ctx.history("run")
    for report in ("run", "run/", ".", "./run/.."):
        ctx.refused("replay", ["--scene", deck, "--results", frd, "--report", report] + REPLAY, 2,
                    r"--report '.*' holds --scene '.*deck.inp'")


@case("replay_report_holds_the_results_deeper")
def _(ctx):
    deck, _ = ctx.history()
    _, frd = ctx.history("a/b")
    ctx.refused("replay", ["--scene", deck, "--results", frd, "--report", "a"] + REPLAY, 2,
                r"--report 'a' holds --results '.*run.frd'")


@case("scene_study_output_under_proc")
def _(ctx):
    deck, _ = ctx.history()
    ctx.refused("scene-study", ["--scene", deck, "--surface", "bilinear", "--output", "/proc/x", "--check"], 4,
                r"--output '/proc/x': cannot write")


@case("scene_study_output_dev_null")
def _(ctx):
    deck, _ = ctx.history()
    ctx.refused("scene-study", ["--scene", deck, "--surface", "bilinear", "--output", "/dev/null", "--check"], 4,
                r"--output '/dev/null': .*not a directory")


@case("scene_study_output_under_a_file")
def _(ctx):
    deck, _ = ctx.history()
    ctx.refused("scene-study", ["--scene", deck, "--surface", "bilinear", "--output", "deck.inp/study", "--check"],
                4, r"--output 'deck.inp/study': .*'.*deck.inp' is not a directory")


@case("scene_study_output_file_is_an_input")
def _(ctx):
    # The deck is named as one of the files scene-study writes into --output.
    deck, _ = ctx.history("study")
    os.rename(deck, ctx.path("study", "report.md"))
    ctx.refused("scene-study", ["--scene", "study/report.md", "--surface", "bilinear", "--output", "study",
                                "--check"], 2,
                r"--output file 'report.md' '.*report.md' and --scene '.*report.md' are the same file")


@case("scene_study_face_output_under_proc")
def _(ctx):
    ctx.refused("scene-study", ["--face", "tri6", "--general", "--output", "/proc/x", "--check"], 4,
                r"--output '/proc/x': cannot write")


@case("evaluate_net_report_under_proc")
def _(ctx):
    weights = os.path.join(ctx.a.source_dir, "data", "weights", "bilinear-8.h5")
    pairs = os.path.join(ctx.a.source_dir, "data", "examples", "raw-bilinear.csv")
    for report, code, pattern in (("/proc/x/y", 4, r"--report '/proc/x/y': cannot write"),
                                  ("/dev/null", 4, r"--report '/dev/null': .*not a directory")):
        ctx.refused("evaluate-net", ["--pairs", pairs, "--weights", weights, "--report", report], code, pattern)


@case("gen_configs_output_under_proc")
def _(ctx):
    deck, frd = ctx.history()
    ctx.refused("gen-configs", ["--scene", deck, "--results", frd, "--output", "/proc/x/y.csv"], 4,
                r"--output: cannot write '/proc/x/y.csv'")
    ctx.refused("gen-configs", ["--scene", deck, "--results", frd, "--output", frd], 2,
                r"--output '.*run.frd' and --results '.*run.frd' are the same file")


@case("train_net_outputs_under_proc")
def _(ctx):
    data = ctx.path("tiny.h5")
    r = ctx.run("gen-configs", ["--config", os.path.join(ctx.a.source_dir, "configs", "tiny.toml"), "--output", data,
                                "--quiet"])
    if r.returncode != 0:
        raise Failure("gen-configs tiny: " + r.stderr)
    ctx.refused("train-net", ["--data", data, "--output", "/proc/x/net.h5", "--epochs", "1"], 4,
                r"--output: cannot write '/proc/x/net.h5'")
    ctx.refused("train-net", ["--data", data, "--output", "net.h5", "--export-header", "/proc/x/net.h", "--epochs",
                              "1"], 4, r"--export-header: cannot write '/proc/x/net.h'")


# ---- Doubtful cases ----

@case("gen_configs_empty_increment")
def _(ctx):
    deck, frd = ctx.history()
    ctx.refused("gen-configs", ["--scene", deck, "--results", frd, "--increment", "", "--output", "pairs.csv"], 2,
                r"--increment: expected a number from 1, 'last' or 'all', got ''")


def main():
    p = argparse.ArgumentParser()
    for tool in ("gen-configs", "train-net", "evaluate-net", "replay", "scene-study"):
        p.add_argument("--" + tool, default="")
    p.add_argument("--source-dir", default="")
    p.add_argument("--work", default="")
    p.add_argument("--list", action="store_true")
    p.add_argument("--case")
    a = p.parse_args()
    if a.list:
        print(";".join(CASES))
        return 0
    work = os.path.join(a.work, a.case)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        CASES[a.case](Context(a, work))
    except Failure as e:
        print("FAIL: " + str(e))
        return 1
    print("PASS " + a.case)
    return 0


if __name__ == "__main__":
    sys.exit(main())
