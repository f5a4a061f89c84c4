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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from case_registry import Cases, Failure  # noqa: E402  (tests/apps/case_registry.py)

CASES = Cases()
case = CASES.case


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


def rewrite_node_block(frd, move=None, extra=()):
    """Rewrites the node block of `frd`: each node's coordinates through `move`, and the nodes `extra` ((id, x, y,
    z), ids the deck does not have) added, NUMNOD updated (the long format ccx writes: I10, 3E12.5)."""
    with open(frd) as f:
        lines = f.read().split("\n")
    start = next(i for i, line in enumerate(lines) if line.startswith("    2C"))
    end = next(i for i in range(start, len(lines)) if lines[i].startswith(" -3"))
    records = []
    for line in lines[start + 1:end]:
        node, xyz = int(line[3:13]), [float(line[13 + 12 * k:25 + 12 * k]) for k in range(3)]
        records.append((node, move(*xyz) if move else xyz))
    records += [(n, [x, y, z]) for n, x, y, z in extra]
    header = lines[start]
    lines[start] = header[:24] + "%12d" % len(records) + header[36:]
    lines[start + 1:end] = [" -1%10d%12.5E%12.5E%12.5E" % (n, *xyz) for n, xyz in records]
    with open(frd, "w") as f:
        f.write("\n".join(lines))


def rotated(x, y, z):
    c, s = 0.8660254037844387, 0.5
    return [c * x - s * y, s * x + c * y, z]


@case("results_of_another_mesh")
def _(ctx):
    # Another mesh with the deck's node ids (scaled, rotated, moved) was accepted silently, its coordinates
    # replacing the deck's: exit 3 naming the node block's line and the first node that differs, in every tool
    # that reads a .frd; --trust-results-nodes takes the file's coordinates.
    deck, frd = ctx.history()
    original = open(frd).read()
    for name, move in (("scaled", lambda x, y, z: [1.5 * x, 1.5 * y, 1.5 * z]), ("rotated", rotated),
                       ("moved", lambda x, y, z: [x + 0.05, y, z])):
        with open(frd, "w") as f:
            f.write(original)
        rewrite_node_block(frd, move)
        pattern = r"run\.frd':3: node block \('    2C'\): node \d+ is at .*, the deck's at .* apart, more than " \
                  r".*--trust-results-nodes"
        ctx.refused("gen-configs", ["--scene", deck, "--results", frd, "--output", "pairs.csv"], 3, pattern)
        ctx.refused("replay", ["--scene", deck, "--results", frd, "--report", "report"] + REPLAY, 3, pattern)
        ctx.refused("scene-study", ["--scene", deck, "--results", frd, "--surface", "bilinear", "--output", "study",
                                    "--count", "100", "--epochs", "1", "--train-networks", "never", "--quiet"], 3,
                    pattern)
        r = ctx.run("gen-configs", ["--scene", deck, "--results", frd, "--output", name + ".csv",
                                    "--trust-results-nodes"])
        if r.returncode != 0:
            raise Failure(f"{name}: --trust-results-nodes: exit {r.returncode}\n{r.stderr}")
    # The rounding of the node block (E12.5) is no difference.
    with open(frd, "w") as f:
        f.write(original)
    rewrite_node_block(frd, lambda x, y, z: [x * (1 + 4e-6), y * (1 - 4e-6), z * (1 + 4e-6)])
    r = ctx.run("gen-configs", ["--scene", deck, "--results", frd, "--output", "rounded.csv"])
    if r.returncode != 0:
        raise Failure(f"a node block rounded differently is refused: exit {r.returncode}\n{r.stderr}")


@case("results_of_a_deck_with_shell_elements")
def _(ctx):
    # CalculiX expands shell and beam elements into solids with new nodes and writes those: the message said "the
    # results file does not belong to the deck"; it says what was found and what to do.
    deck, frd = ctx.history()
    with open(deck, "a") as f:
        f.write("*NODE\n90001, 0, 0, 5\n90002, 1, 0, 5\n90003, 1, 1, 5\n90004, 0, 1, 5\n"
                "*ELEMENT, TYPE=S4, ELSET=SHELL\n9001, 90001, 90002, 90003, 90004\n")
    rewrite_node_block(frd, extra=[(100001 + k, k % 2, k // 4, 5.0 + 0.1 * (k % 3)) for k in range(8)])
    ctx.refused("gen-configs", ["--scene", deck, "--results", frd, "--output", "pairs.csv"], 3,
                r"run\.frd':3: node block \('    2C'\): node 90001 \(of element 9001\) and 3 other node\(s\) .*not "
                r"in it, and 8 node\(s\) the deck does not have: element 9001 is of type S4, a shell, beam, membrane "
                r"or plane element, which CalculiX expands into solid elements with new nodes .*Use a deck whose "
                r"elements are solid")


PLATE = """*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 0.2
6, 1, 0, 0.2
7, 1, 1, 0.2
8, 0, 1, 0.2
101, 0.5, 0.5, 0.3
102, 0.5, 0.5, -5.0
103, 7, 7, 7
*ELEMENT, TYPE=C3D8, ELSET=PLATE
1, 1, 2, 3, 4, 5, 6, 7, 8
*NSET, NSET=SLAVES
101, 102, 103
*SURFACE, NAME=SSLAVE, TYPE=NODE
SLAVES
*SURFACE, NAME=SMASTER, TYPE=ELEMENT
PLATE, S2
*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE
SSLAVE, SMASTER
"""


@case("deep_penetration_counted")
def _(ctx):
    # A slave node driven through a thin master beyond the capture distance got no_segment, a contact lost without
    # a word: the summary counts the nodes beyond capture and those of them behind the master, and stderr warns.
    # Node 101 is above the plate (found), 102 five plate thicknesses under its top face (behind it, far beyond
    # the capture distance), 103 far away in front.
    with open(ctx.path("plate.inp"), "w") as f:
        f.write(PLATE)
    r = ctx.run("gen-configs", ["--scene", "plate.inp", "--output", "pairs.csv"])
    if r.returncode != 0:
        raise Failure(f"exit {r.returncode}\n{r.stdout}{r.stderr}")
    if not re.search(r"\n  beyond capture +2 slave nodes \(no face within [0-9.e+-]+\), 1 of them behind the master "
                     r"surface\n", r.stdout):
        raise Failure("the summary does not count the nodes beyond capture:\n" + r.stdout)
    if not re.search(r"warning: 1 slave node\(s\) of pair 0 lie behind the master surface .*--capture_distance",
                     r.stderr):
        raise Failure("no warning on stderr:\n" + r.stderr)


@case("geometry_keywords_named")
def _(ctx):
    # Keywords that change the contact geometry CalculiX uses were skipped without a word: each is named on stderr
    # (file, line, the keyword line) and counted in the summary; one in an included file too.
    deck = PLATE.replace("*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE",
                         "*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE, Adjust=0.01")
    deck += "*Clearance, master=SMASTER, slave=SSLAVE, value=-0.1\n*INCLUDE, INPUT=more.inp\n"
    with open(ctx.path("plate.inp"), "w") as f:
        f.write(deck)
    with open(ctx.path("more.inp"), "w") as f:
        f.write("** shrink fit\n*CONTACT INTERFERENCE, SHRINK\nSSLAVE, SMASTER\n")
    r = ctx.run("gen-configs", ["--scene", "plate.inp", "--output", "pairs.csv"])
    if r.returncode != 0:
        raise Failure(f"exit {r.returncode}\n{r.stdout}{r.stderr}")
    for line, text in ((21, r"\*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE, Adjust=0\.01"),
                       (23, r"\*Clearance, master=SMASTER, slave=SSLAVE, value=-0\.1")):
        if not re.search(r"gen-configs: warning: 'plate\.inp':%d: %s: this keyword changes the contact geometry"
                         % (line, text), r.stderr):
            raise Failure(f"line {line} not named on stderr:\n{r.stderr}")
    if not re.search(r"warning: '.*more\.inp':2: \*CONTACT INTERFERENCE, SHRINK: this keyword", r.stderr):
        raise Failure("the included file's keyword is not named:\n" + r.stderr)
    if not re.search(r"\n  not applied +3 keyword\(s\) that change the contact geometry", r.stdout):
        raise Failure("the summary does not count them:\n" + r.stdout)


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
        CASES[a.case][0](Context(a, work))
    except Failure as e:
        print("FAIL: " + str(e))
        return 1
    print("PASS " + a.case)
    return 0


if __name__ == "__main__":
    sys.exit(main())
