#!/usr/bin/env python3
"""Bad input for the apps (issue 5, part 3): malformed CSV, bad config files, bad options, missing or wrong
files. Every case runs one app in a fresh directory and checks:

  - the documented exit code (lib/core/error.hpp: 2 usage/config, 3 bad input data, 4 I/O);
  - a message on stderr naming the file and the field or line (a regular expression per case);
  - no crash: no signal, no "terminate called", no stack trace, no "internal" error;
  - nothing left behind: the directory holds exactly the files it held before the run (no output, no
    temporary file), and an output that existed before a failed run is unchanged.

Valid-but-hostile inputs (nan, inf, 1e400, a BOM, CRLF, quoted commas) must succeed with no NaN or inf printed
as a result.

Usage: bad_inputs.py --gen-configs PATH [--train-net PATH --evaluate-net PATH] --work DIR (--list | --case NAME | --all)
"""
import argparse
import os
import re
import resource
import shutil
import stat
import subprocess
import sys
import threading

HEADER = "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz"
ROW = "0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,0.1"
NORMALS = "nax,nay,naz,nbx,nby,nbz,ncx,ncy,ncz,ndx,ndy,ndz"

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from case_registry import Cases, Failure  # noqa: E402  (tests/apps/case_registry.py)

CASES = Cases()
SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def case(name, needs=("gen-configs",)):
    return CASES.case(name, needs)


class Context:
    def __init__(self, tools, directory):
        self.tools = tools
        self.dir = directory

    def path(self, name):
        return os.path.join(self.dir, name)

    def write(self, name, content):
        mode = "wb" if isinstance(content, bytes) else "w"
        with open(self.path(name), mode, **({} if mode == "wb" else {"newline": ""})) as f:
            f.write(content)
        return self.path(name)

    def run(self, tool, args, timeout=120, env=None, preexec_fn=None, raw=False):
        command = [self.tools[tool]] + args
        full_env = dict(os.environ, **env) if env else None
        try:
            p = subprocess.run(command, cwd=self.dir, capture_output=True, timeout=timeout, env=full_env,
                               preexec_fn=preexec_fn)
        except subprocess.TimeoutExpired:
            raise Failure(f"hang: {' '.join(command)} ran past {timeout} s")
        if raw:
            return p.returncode, p.stdout, p.stderr.decode("utf-8", "replace")
        return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")

    def expect_failure(self, tool, args, code, pattern, outputs=(), env=None, preexec_fn=None):
        """Runs a command that must fail with `code`, a stderr matching `pattern`, and leave nothing behind."""
        before = snapshot(self.dir)
        rc, out, err = self.run(tool, args, env=env, preexec_fn=preexec_fn)
        report = f"command: {tool} {' '.join(args)}\nexit: {rc}\nstderr:\n{err}\nstdout:\n{out[-2000:]}"
        if rc < 0:
            raise Failure(f"killed by signal {-rc}\n{report}")
        # "[requirement" and "failed at": the internal check macro's suffix, which user-facing errors never
        # carry (a message must read cleanly, without source paths).
        for bad in ("terminate called", "Traceback", "Aborted", "Segmentation fault", "error: internal",
                    "AddressSanitizer", "runtime error", "[requirement", "failed at"):
            if bad in err:
                raise Failure(f"crash marker '{bad}' in stderr\n{report}")
        if rc != code:
            raise Failure(f"exit status {rc}, expected {code}\n{report}")
        if not re.search(pattern, err, re.S):
            raise Failure(f"stderr does not match {pattern!r}\n{report}")
        after = snapshot(self.dir)
        if after != before:
            added = sorted(set(after) - set(before))
            changed = sorted(k for k in before if k in after and before[k] != after[k])
            removed = sorted(set(before) - set(after))
            raise Failure(f"files left behind or touched: added {added}, changed {changed}, removed {removed}\n{report}")
        for o in outputs:
            if os.path.exists(self.path(o)) and o not in before:
                raise Failure(f"output {o} left behind\n{report}")

    def expect_success(self, tool, args, env=None, raw=False):
        rc, out, err = self.run(tool, args, env=env, raw=raw)
        if rc != 0:
            raise Failure(f"exit status {rc}, expected 0\ncommand: {tool} {' '.join(args)}\nstderr:\n{err}")
        return out, err


def snapshot(directory):
    """Every file under `directory` with its content hash (a symbolic link: where it points), and every
    directory."""
    result = {}
    for root, dirs, files in os.walk(directory):
        for name in dirs:
            result[os.path.relpath(os.path.join(root, name), directory) + "/"] = "directory"
        for name in files:
            full = os.path.join(root, name)
            if os.path.islink(full):
                result[os.path.relpath(full, directory)] = "-> " + os.readlink(full)
                continue
            if not stat.S_ISREG(os.stat(full).st_mode):
                result[os.path.relpath(full, directory)] = "special"
                continue
            with open(full, "rb") as f:
                result[os.path.relpath(full, directory)] = hash(f.read())
    return result


def read_csv_rows(path):
    with open(path, newline="") as f:
        import csv
        return list(csv.reader(f))


def no_non_finite_results(path, value_columns):
    rows = read_csv_rows(path)
    header = rows[0]
    for r, row in enumerate(rows[1:], start=2):
        for name in value_columns:
            v = row[header.index(name)].strip().lower()
            if "nan" in v or "inf" in v:
                raise Failure(f"{path}:{r}: column {name} holds '{v}': a non-finite value printed as a result")
    return rows


# ------------------------------------------------------------------------------------------------------
# gen-configs label mode: malformed RAW.csv. Message: 'FILE':LINE: what (SPEC 6: file, line and column).

def label(ctx, content, code, pattern, surface="bilinear"):
    src = ctx.write("in.csv", content) if content is not None else ctx.path("in.csv")
    ctx.expect_failure("gen-configs", ["--surface", surface, "--input", src, "--output", "out.csv"], code, pattern,
                       outputs=["out.csv"])


# Label-mode inputs gen-configs refuses, one case each: (case, the CSV text, exit code, the stderr pattern).
LABEL_CASES = [
    ("csv_text_in_number", f"{HEADER}\n{ROW}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,abc,0.1\n", 3,
     r"^error: '[^']*in\.csv':3: column 'sy': 'abc' is not a number\n$"),
    ("csv_empty_field", f"{HEADER}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,\n", 3,
     r"in\.csv':2: column 'sz': '' is not a number"),
    ("csv_missing_column", "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4\n", 3,
     r"in\.csv':1: missing column 'sz'"),
    ("csv_ragged_row_short", f"{HEADER}\n{ROW}\n{ROW}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4\n", 3,
     r"in\.csv':4: ragged row: 14 fields, the header has 15"),
    ("csv_ragged_row_long", f"{HEADER}\n{ROW},7\n", 3,
     r"in\.csv':2: ragged row: 16 fields, the header has 15"),
    ("csv_empty_file", "", 3,
     r"in\.csv': empty file: expected a header row and data rows"),
    ("csv_blank_lines_only", "\n  \n\r\n", 3,
     r"in\.csv': empty file"),
    ("csv_duplicate_column", f"{HEADER},ax\n{ROW},0\n", 3,
     r"in\.csv':1: duplicate column 'ax' in the header"),
    ("csv_unterminated_quote", f"{HEADER},note\n{ROW},fine\n{ROW},\"never closed\n{ROW},x\n", 3,
     r"in\.csv':3: column 16 \('note'\): unterminated quoted field"),
    ("csv_binary_garbage", bytes(range(256)) * 4, 3,
     r"^error: '[^']*in\.csv'"),
    ("input_file_missing", None, 2,
     r"--input: File does not exist: .*in\.csv"),
    ("csv_utf16_with_byte_order_mark", f"{HEADER}\n{ROW}\n".encode("utf-16"), 3,
     r"^error: '[^']*in\.csv': the file is UTF-16 \(little-endian\) text \(by its byte-order mark\); save it as "
     r"UTF-8 or ASCII\n$"),
    ("csv_utf16_without_byte_order_mark", f"{HEADER}\n{ROW}\n".encode("utf-16-be"), 3,
     r"^error: '[^']*in\.csv':1: the header holds NUL bytes: UTF-16 text without a byte-order mark"),
    ("csv_cr_only_line_ends", f"{HEADER}\r{ROW}\r{ROW}\r", 3,
     r"^error: '[^']*in\.csv':1: carriage return without a line feed \(a file with CR-only line ends\?\)"),
]
for _name, _text, _code, _pattern in LABEL_CASES:
    case(_name)(lambda ctx, text=_text, code=_code, pattern=_pattern: label(ctx, text, code, pattern))


@case("csv_header_only")
def _(ctx):
    # A header alone is a RAW.csv of no configurations (SPEC 7: a pair without slave nodes gives one, and it is
    # valid input): exit 0, the header with the label columns and no row, a warning saying so. Not so for a
    # dataset of the report mode, which needs rows (evaluate_net_pairs_header_only).
    src = ctx.write("in.csv", f"id,{HEADER}\r\n")
    _, err = ctx.expect_success("gen-configs", ["--surface", "bilinear", "--input", src, "--output", "out.csv"])
    if not re.search(r"warning: '[^']*in\.csv' has a header and no data rows: '[^']*out\.csv' has the header only",
                     err):
        raise Failure(f"no warning about the empty input:\n{err}")
    rows = read_csv_rows(ctx.path("out.csv"))
    if rows != [["id"] + HEADER.split(",") + ["xi", "eta", "status", "gap", "iterations"]]:
        raise Failure(f"expected the header and the label columns alone, got {rows}")


@case("evaluate_net_pairs_header_only", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    net = make_network(ctx, make_dataset(ctx))
    src = ctx.write("in.csv", f"{HEADER}\n")
    ctx.expect_failure("evaluate-net", ["--weights", net, "--pairs", src, "--report", "rep", "--quiet"], 3,
                       r"in\.csv': header only: expected at least one data row")


@case("csv_unnamed_and_repeated_columns_are_copied")
def _(ctx):
    # SPEC 6: columns a tool does not read are copied unchanged, whatever their names: pandas writes its index
    # as a column named "", and two notes may share a name. Only a column the tool reads must be named once.
    src = ctx.write("in.csv", f",note,{HEADER},note\n7,a,{ROW},b\n")
    ctx.expect_success("gen-configs", ["--surface", "bilinear", "--input", src, "--output", "out.csv"])
    rows = read_csv_rows(ctx.path("out.csv"))
    header = ["", "note"] + HEADER.split(",") + ["note", "xi", "eta", "status", "gap", "iterations"]
    if len(rows) != 2 or rows[0] != header or rows[1][:2] != ["7", "a"] or rows[1][17] != "b" or rows[1][20] != "ok":
        raise Failure(f"expected the unnamed and repeated columns copied in place, got {rows}")


@case("csv_gregory_without_normal_columns")
def _(ctx):
    label(ctx, f"{HEADER}\n{ROW}\n", 3, r"in\.csv':1: missing column 'nax'", surface="gregory")


@case("input_is_a_directory")
def _(ctx):
    os.mkdir(ctx.path("in.csv"))
    label(ctx, None, 2, r"--input: .*in\.csv")


@case("output_directory_missing")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("gen-configs", ["--input", src, "--output", "no/such/dir/out.csv"], 4,
                       r"^error: --output: cannot write 'no/such/dir/out\.csv': directory 'no/such/dir' does not exist\n$")


@case("output_is_a_directory")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    os.mkdir(ctx.path("out.csv"))
    ctx.write("out.csv/keep", "x")
    ctx.expect_failure("gen-configs", ["--input", src, "--output", "out.csv"], 4,
                       r"^error: --output: cannot write 'out\.csv': it is a directory\n$")


@case("failed_run_keeps_previous_output")
def _(ctx):
    # An earlier complete output is neither removed nor overwritten by a run that fails.
    ctx.write("out.csv", "an earlier complete output\n")
    label(ctx, f"{HEADER}\n{ROW}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,x,0.1\n", 3, r"in\.csv':3: column 'sy'")


@case("unknown_surface")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("gen-configs", ["--surface", "quad", "--input", src, "--output", "out.csv"], 2,
                       r"--surface: quad not in \{bilinear,gregory\}")


@case("unknown_option")
def _(ctx):
    ctx.expect_failure("gen-configs", ["--output", "out.h5", "--d_xy_point", "3"], 2,
                       r"The following arguments? (was|were) not expected: .*--d_xy_point")


@case("missing_required_output")
def _(ctx):
    ctx.expect_failure("gen-configs", [], 2, r"--output is required")


@case("nan_inf_overflow_rows_are_invalid_not_printed")
def _(ctx):
    rows = [ROW,
            "nan,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,0.1",
            "0,0,0,inf,0,0,1,1,0,0,1,0,0.3,0.4,0.1",
            "0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,-Infinity",
            "0,0,0,1,0,0,1,1,0,0,1,0,1e400,0.4,0.1",
            "0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,1e-400",
            "0,0,0,0,0,0,1,1,0,0,1,0,0.3,0.4,0.1"]
    src = ctx.write("in.csv", HEADER + "\n" + "\n".join(rows) + "\n")
    ctx.expect_success("gen-configs", ["--input", src, "--output", "out.csv"])
    out = no_non_finite_results(ctx.path("out.csv"), ["xi", "eta", "gap", "iterations"])
    status = [r[out[0].index("status")] for r in out[1:]]
    expected = ["ok", "invalid", "invalid", "invalid", "invalid", "ok", "degenerate"]
    if status != expected:
        raise Failure(f"statuses {status}, expected {expected}")


@case("bom_crlf_quotes_and_extra_columns_are_read")
def _(ctx):
    text = ("\ufeffid,note," + HEADER + "\r\n" +
            "1,\"a, quoted \"\"note\"\"\"," + ROW + "\r\n" +
            "2,\"two\nlines\", " + ROW.replace(",", " , ") + " \r\n")
    src = ctx.write("in.csv", text.encode("utf-8"))
    ctx.expect_success("gen-configs", ["--input", src, "--output", "out.csv"])
    out = no_non_finite_results(ctx.path("out.csv"), ["xi", "eta", "gap"])
    if [r[1] for r in out[1:]] != ["a, quoted \"note\"", "two\nlines"] or \
            [r[out[0].index("status")] for r in out[1:]] != ["ok", "ok"]:
        raise Failure(f"extra columns not copied or rows not labelled: {out}")


@case("scene_without_segments_warns", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    # A 2-D deck (CPE4R, x,y nodes): a well-formed pair with nothing to search. Valid input (exit 0, the header
    # alone), but a warning on stderr names the skipped faces, where a script checking only the exit code
    # would otherwise take it for an empty scene.
    deck = ctx.write("plane.inp", "*NODE\n1, 0., 0.\n2, 1., 0.\n3, 1., 1.\n4, 0., 1.\n"
                                  "5, 0., 1.1\n6, 1., 1.1\n7, 1., 2.1\n8, 0., 2.1\n"
                                  "*ELEMENT, TYPE=CPE4R\n1, 1, 2, 3, 4\n2, 5, 6, 7, 8\n"
                                  "*SURFACE, NAME=MASTER\n1, S3\n*SURFACE, NAME=SLAVE\n2, S1\n"
                                  "*CONTACT PAIR, INTERACTION=I, TYPE=SURFACE TO SURFACE\nSLAVE, MASTER\n")
    _, err = ctx.expect_success("gen-configs", ["--scene", deck, "--surface", "bilinear", "--output", "pairs.csv"])
    if not re.search(r"warning: contact pair 0 of .*plane\.inp has 0 master segments and 0 slave nodes "
                     r"\(faces skipped, master: CPE4R face 1; slave: CPE4R face 1\)", err):
        raise Failure(f"no warning naming the skipped faces:\n{err}")
    with open(ctx.path("pairs.csv")) as f:
        lines = f.read().splitlines()
    if len(lines) != 1 or not lines[0].startswith("slave,a,b,c,d,"):
        raise Failure(f"expected the header alone, got {lines[:3]}")
    # SPEC 7: the pairs file is a valid RAW.csv for evaluate-net --input, this one too: the header alone out.
    net = make_network(ctx, make_dataset(ctx))
    _, err = ctx.expect_success("evaluate-net", ["--weights", net, "--input", "pairs.csv", "--output", "pred.csv"])
    if "has a header and no data rows" not in err:
        raise Failure(f"no warning about the empty input:\n{err}")
    pred = read_csv_rows(ctx.path("pred.csv"))
    computed = ["xi", "eta", "status"]  # replace the pairs file's label columns of the same name
    if pred != [[c for c in lines[0].split(",") if c not in computed] + computed]:
        raise Failure(f"expected the pairs header with the prediction columns alone, got {pred}")


@case("scene_pair_missing_names_the_deck")
def _(ctx):
    # A deck without *CONTACT PAIR, and a pair number past the last: usage errors (exit 2) naming the deck.
    body = "*NODE\n1, 0., 0., 0.\n2, 1., 0., 0.\n3, 1., 1., 0.\n4, 0., 1., 0.\n"
    ctx.write("nopair.inp", body)
    ctx.expect_failure("gen-configs", ["--scene", "nopair.inp", "--surface", "bilinear", "--output", "p.csv"], 2,
                       r"'[^']*nopair\.inp': the deck has no \*CONTACT PAIR")


@case("scene_deck_or_include_not_a_regular_file")
def _(ctx):
    # An *INCLUDE of a directory read as an empty file (exit 0, nothing said); --scene /dev/zero read 4 GB
    # into memory for 16 s and went on. Both are refused at once (exit 3), naming the file and the line.
    os.makedirs(ctx.path("meshes"))
    ctx.write("dir.inp", "*NODE\n1, 0., 0., 0.\n*INCLUDE, INPUT=meshes\n")
    ctx.expect_failure("gen-configs", ["--scene", "dir.inp", "--surface", "bilinear", "--output", "p.csv"], 3,
                       r"^error: 'dir\.inp':3: \*INCLUDE: INPUT='meshes' \(meshes\) is a directory, not a regular "
                       r"file\n$", outputs=["p.csv"])
    ctx.write("zero.inp", "*NODE\n1, 0., 0., 0.\n*INCLUDE, INPUT=/dev/zero\n")
    ctx.expect_failure("gen-configs", ["--scene", "zero.inp", "--surface", "bilinear", "--output", "p.csv"], 3,
                       r"^error: 'zero\.inp':3: \*INCLUDE: INPUT='/dev/zero' .*is a character device, not a regular "
                       r"file\n$", outputs=["p.csv"])
    ctx.expect_failure("gen-configs", ["--scene", "/dev/zero", "--surface", "bilinear", "--output", "p.csv"], 3,
                       r"^error: '/dev/zero' is a character device, not a regular file", outputs=["p.csv"])


@case("scene_deck_long_line_and_huge_field")
def _(ctx):
    # A 10 MB field was copied whole into the message; a line longer than any deck needs is an error naming file
    # and line, and a long field within a line is quoted short.
    ctx.write("long.inp", "*NODE\n1, 0., " + "7" * 10_000_000 + ", 0.\n")
    ctx.expect_failure("gen-configs", ["--scene", "long.inp", "--surface", "bilinear", "--output", "p.csv"], 3,
                       r"^error: 'long\.inp':2: the line is longer than 65536 bytes[^\n]*\n$", outputs=["p.csv"])
    ctx.write("field.inp", "*NODE\n1, 0., 0., 0.\n2, 0., " + "x" * 60_000 + ", 0.\n")
    ctx.expect_failure("gen-configs", ["--scene", "field.inp", "--surface", "bilinear", "--output", "p.csv"], 3,
                       r"^error: 'field\.inp':3: \*NODE: node 2: field 3: 'x{40}\.\.\.' \(60000 bytes\) is not a "
                       r"finite number\n$", outputs=["p.csv"])


@case("scene_deck_encoding_and_line_ends")
def _(ctx):
    # Binary, UTF-16 and CR-only decks were reported as "the deck has no *CONTACT PAIR" (exit 2): the encoding
    # or the line ends is named instead (exit 3).
    deck = "*NODE\r\n1, 0., 0., 0.\r\n*CONTACT PAIR\r\nA, B\r\n"
    cases = [("utf16.inp", deck.encode("utf-16"), r"'utf16\.inp':1: the file is UTF-16 \(little-endian\) text"),
             ("utf16-bare.inp", deck.encode("utf-16-le"), r"'utf16-bare\.inp':1: column 2: a NUL byte: UTF-16"),
             ("cr.inp", deck.replace("\r\n", "\r").encode(), r"'cr\.inp':1: column 6: a carriage return without a "
                                                              r"line feed \(a file with CR-only line ends\?\)"),
             ("binary.inp", bytes(range(1, 256)) * 4, r"'binary\.inp':1: column 1: control character 0x01: a binary "
                                                      r"file")]
    for name, content, pattern in cases:
        ctx.write(name, content)
        ctx.expect_failure("gen-configs", ["--scene", name, "--surface", "bilinear", "--output", "p.csv"], 3,
                           "^error: " + pattern, outputs=["p.csv"])


@case("omp_num_threads_beyond_the_cap")
def _(ctx):
    # OMP_NUM_THREADS=100000 crashed every parallel region inside libgomp (--threads is capped at 1024, OpenMP's
    # default was not), and label mode left its temporary file: the default is capped too, with a warning.
    env = {"OMP_NUM_THREADS": "100000"}
    _, err = ctx.expect_success("gen-configs", ["--surface", "bilinear", "--input", ctx.write("in.csv", f"{HEADER}\n" +
                                                                                              f"{ROW}\n" * 3000),
                                                "--output", "labels.csv"], env=env)
    if "warning: OpenMP's default of 100000 threads (OMP_NUM_THREADS) is more than 1024; using 1024" not in err:
        raise Failure(f"no warning about the capped thread count:\n{err}")
    rows = no_non_finite_results(ctx.path("labels.csv"), ["xi", "eta", "gap"])
    if len(rows) != 3001 or any(r[rows[0].index("status")] != "ok" for r in rows[1:]):
        raise Failure(f"expected 3000 rows labelled ok, got {len(rows) - 1}")
    ctx.expect_success("gen-configs", ["--config", os.path.join(SOURCE_DIR, "configs", "tiny.toml"), "--output",
                                       "tiny.h5", "--quiet"], env=env)
    if sorted(os.listdir(ctx.dir)) != ["in.csv", "labels.csv", "tiny.h5", "tiny.h5.config.toml"]:
        raise Failure(f"unexpected files (a temporary left?): {sorted(os.listdir(ctx.dir))}")


# ------------------------------------------------------------------------------------------------------
# Config files and option values (enumeration mode). Message: config file 'F', line N, key K.

def config(ctx, text, code, pattern, extra=()):
    ctx.write("c.toml", text)
    ctx.expect_failure("gen-configs", ["--config", "c.toml", "--output", "out.h5", "--quiet"] + list(extra), code,
                       pattern, outputs=["out.h5", "out.h5.config.toml"])


# Config files gen-configs refuses, one case each: (case, the file, exit code, the stderr pattern).
CONFIG_CASES = [
    ("config_unknown_key", "[gen-configs]\nd_xy_points = 4\nd_xy_pionts = 4\n", 2,
     r"^error: config file 'c\.toml': line 3: unknown key 'd_xy_pionts' in \[gen-configs\] "
     r"\(expected one of: [^)]*d_xy_points"),
    ("config_unknown_section", "[gen-configs]\nd_xy_points = 4\n[gen-config]\nc_xy_points = 4\n", 2,
     r"^error: config file 'c\.toml': line 3: unknown section \[gen-config\] \(expected one of"),
    ("config_malformed_section_header", "[gen-configs\nd_xy_points = 4\n", 2,
     r"^error: config file 'c\.toml': line 1, column \d+: not valid TOML: .*table header"),
    ("config_key_outside_any_section", "# a study\nd_xy_points = 4\n[gen-configs]\n", 2,
     r"^error: config file 'c\.toml': line 2: key 'd_xy_points' is outside any section"),
    ("config_value_out_of_range", "[gen-configs]\n\nd_xy_points = 0\n", 2,
     r"^error: config file 'c\.toml', line 3, key 'd_xy_points': --d_xy_points: must be an integer in 1\.\.400, "
     r"got '0'\n$"),
    ("config_negative_limit", "[gen-configs]\nz_limit = -0.3\n", 2,
     r"^error: config file 'c\.toml', line 2, key 'z_limit': --z_limit: must be a finite number > 0, got -0\.3\n$"),
    ("config_wrong_type", "[gen-configs]\nconvex = \"maybe\"\n", 2,
     r"^error: config file 'c\.toml', line 2, key 'convex': expected a boolean \(true or false\), got a string\n$"),
    ("config_bare_word_is_not_toml", "[gen-configs]\nconvex = maybe\n", 2,
     r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML"),
    ("config_string_for_an_integer", "[gen-configs]\n\nd_xy_points = \"4\"\n", 2,
     r"^error: config file 'c\.toml', line 3, key 'd_xy_points': expected an integer, got a string\n$"),
    ("config_float_for_an_integer", "[gen-configs]\nd_xy_points = 4.5\n", 2,
     r"^error: config file 'c\.toml', line 2, key 'd_xy_points': expected an integer, got a floating-point number"),
    ("config_duplicate_key", "[gen-configs]\nd_xy_points = 8\nd_xy_points = 9\n", 2,
     r"^error: config file 'c\.toml': line 3, column \d+: not valid TOML: .*redefine.*'d_xy_points'"),
    ("config_duplicate_section", "[gen-configs]\nd_xy_points = 8\n[train-net]\n[gen-configs]\nc_xy_points = 9\n", 2,
     r"^error: config file 'c\.toml': line 4, column \d+: not valid TOML: .*gen-configs"),
    ("config_nested_table", "[gen-configs.grid]\nd_xy_points = 8\n", 2,
     r"^error: config file 'c\.toml': line 1: unknown key 'grid' in \[gen-configs\]"),
    ("config_array_of_tables", "[[gen-configs]]\nd_xy_points = 8\n", 2,
     r"^error: config file 'c\.toml': line 1: \[\[gen-configs\]\] is an array of tables"),
    ("config_infinite_limit", "[gen-configs]\nxy_limit = inf\n", 2,
     r"^error: config file 'c\.toml', line 2, key 'xy_limit': --xy_limit: must be a finite number > 0, got inf\n$"),
    ("config_min_angle_above_max", "[gen-configs]\nmin_angle_degrees = 100\nmax_angle_degrees = 90\n", 2,
     r"^error: min_angle_degrees 100 is above max_angle_degrees 90: no segment could pass\n$"),
    ("config_bad_choice", "[gen-configs]\nsurface = \"quad\"\n", 2,
     r"^error: config file 'c\.toml', line 2, key 'surface': --surface: quad not in"),
    ("config_unterminated_string", "[gen-configs]\noutput = \"never closed\n", 2,
     r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML: .*string"),
    ("config_two_values", "[gen-configs]\nd_xy_points = 4 5\n", 2,
     r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML"),
    ("config_text_after_string", "[gen-configs]\nsurface = \"bilinear\" x\n", 2,
     r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML: .*saw 'x'"),
    ("config_line_without_value", "[gen-configs]\nquiet\n", 2,
     r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML: .*expected '='"),
]
for _name, _text, _code, _pattern in CONFIG_CASES:
    case(_name)(lambda ctx, text=_text, code=_code, pattern=_pattern: config(ctx, text, code, pattern))


@case("config_value_refused_after_parsing_names_its_line", needs=("gen-configs", "train-net"))
def _(ctx):
    # A value the app checks itself after parsing (hidden = "8,0") came from the config file: its file, line
    # and key are named, as for a value CLI11 refuses (it said "--hidden: ..." alone).
    data = make_dataset(ctx)
    ctx.write("c.toml", "[train-net]\nepochs = 2\nhidden = \"8,0\"\n")
    ctx.expect_failure("train-net", ["--config", "c.toml", "--data", data, "--output", "net.h5"], 2,
                       r"^error: config file 'c\.toml', line 3, key 'hidden': --hidden: expected comma-separated")


@case("config_crlf_bom_underscores_and_spaced_header_are_toml")
def _(ctx):
    # Valid TOML 1.0 that the old line reader refused: a UTF-8 byte-order mark, CRLF line ends, digit
    # separators, blanks inside a table header.
    ctx.write("c.toml", "\ufeff# a study\r\n[ gen-configs ]\r\nd_xy_points = 1_0\r\nc_xy_points = 2\r\n"
                        "s_xy_points = 2\r\nquiet = true\r\n[ train-net ]\r\nhidden = \"8\"\r\n")
    ctx.expect_success("gen-configs", ["--config", "c.toml", "--output", "out.h5"])
    with open(ctx.path("out.h5.config.toml")) as f:
        text = f.read()
    if "\nd_xy_points=10\n" not in text or "\nc_xy_points=2\n" not in text:
        raise Failure(f"the values were not read as written:\n{text}")


@case("config_strings_with_hash_quotes_and_escapes")
def _(ctx):
    # TOML strings: '#' inside quotes is not a comment, escapes are honoured, a literal string is verbatim;
    # the effective config written beside the output reads back to the same settings.
    ctx.write("c.toml", "[gen-configs]  # the study\n"
                        "output = \"d#1 \\\"q\\\" \\\\.h5\"   # comment after a value\n"
                        "surface = 'bilinear'\n"
                        "d_xy_points = 2\nc_xy_points = 2\ns_xy_points = 2\nquiet = true\n")
    ctx.expect_success("gen-configs", ["--config", "c.toml"])
    name = "d#1 \"q\" \\.h5"
    if not os.path.exists(ctx.path(name)) or not os.path.exists(ctx.path(name + ".config.toml")):
        raise Failure(f"expected output {name!r}, found {sorted(os.listdir(ctx.dir))}")
    ctx.expect_success("gen-configs", ["--config", name + ".config.toml", "--output", "again.h5"])
    with open(ctx.path(name + ".config.toml")) as f1, open(ctx.path("again.h5.config.toml")) as f2:
        first = [l for l in f1 if not l.startswith("output=")]
        second = [l for l in f2 if not l.startswith("output=")]
    if first != second:
        raise Failure(f"the effective config changed when read back:\n{''.join(first)}---\n{''.join(second)}")


@case("effective_config_reads_back_identically")
def _(ctx):
    # Values CLI11 accepts on a command line but TOML spells otherwise (".5", "1E-13", a leading zero, a path
    # with quotes, a backslash and a hash) are written as TOML of the option's type; the file given back with
    # --config gives the same settings and the same text.
    name = "we\"ird \\ #1.h5"
    ctx.expect_success("gen-configs", ["--output", name, "--xy_limit", ".5e1", "--tol_param", "1E-13", "--seed", "010",
                                       "--d_xy_points", "2", "--c_xy_points", "2", "--s_xy_points", "3", "--quiet",
                                       "--convex", "true"])
    with open(ctx.path(name + ".config.toml")) as f:
        first = f.read()
    for expected in ("\nxy_limit=5\n", "\ntol_param=1e-13\n", "\nseed=10\n", '\noutput="we\\"ird \\\\ #1.h5"\n',
                     "\nconvex=true\n", "\nquiet=true\n"):
        if expected not in first:
            raise Failure(f"{expected!r} not in the effective config:\n{first}")
    # Given back with --config (under another output: the config file itself is an input now).
    ctx.expect_success("gen-configs", ["--config", name + ".config.toml", "--output", "again.h5"])
    with open(ctx.path("again.h5.config.toml")) as f:
        second = f.read()
    without_output = lambda text: [l for l in text.splitlines() if not l.startswith("output=")]
    if without_output(first) != without_output(second):
        raise Failure(f"the effective config changed when read back:\n{first}---\n{second}")


@case("config_written_by_an_earlier_version_is_read", needs=("gen-configs", "train-net"))
def _(ctx):
    # Earlier versions wrote a defaulted boolean as 1 and a text option as a bare number; such a file, given
    # back with --config, reads as before. Any other integer for a boolean is a type error.
    data = make_dataset(ctx)
    ctx.write("old.toml", f"# effective configuration written by train-net\n[train-net]\ndata=\"{data}\"\nhidden=8\n"
                          "u0=2.0\nrestore_best=1\nepochs=3\ntrain_count=20\nquiet=true\n")
    ctx.expect_success("train-net", ["--config", "old.toml", "--output", "net.h5"])
    with open(ctx.path("net.h5.config.toml")) as f:
        text = f.read()
    if "\nrestore_best=true\n" not in text or '\nhidden="8"\n' not in text:
        raise Failure(f"the old values were not read as such:\n{text}")
    ctx.write("bad.toml", "[train-net]\nrestore_best = 2\n")
    ctx.expect_failure("train-net", ["--config", "bad.toml", "--data", data, "--output", "x.h5"], 2,
                       r"^error: config file 'bad\.toml', line 2, key 'restore_best': expected a boolean \(true or "
                       r"false\), got an integer\n$")


@case("config_file_missing")
def _(ctx):
    ctx.expect_failure("gen-configs", ["--config", "absent.toml", "--output", "out.h5"], 2,
                       r"--config: File does not exist: absent\.toml")


@case("command_line_value_out_of_range")
def _(ctx):
    # The same bad value on the command line is reported as CLI11 does, without a config file.
    config(ctx, "[gen-configs]\nd_xy_points = 4\n", 2, r"^--d_xy_points: must be an integer in 1\.\.400, got '0'",
           extra=["--d_xy_points", "0"])


@case("enumeration_output_directory_missing")
def _(ctx):
    ctx.write("c.toml", "[gen-configs]\nd_xy_points = 2\nc_xy_points = 2\ns_xy_points = 2\n")
    ctx.expect_failure("gen-configs", ["--config", "c.toml", "--output", "no/dir/out.h5", "--quiet"], 4,
                       r"cannot write 'no/dir/out\.h5': directory 'no/dir' does not exist")


# ------------------------------------------------------------------------------------------------------
# Files of the wrong kind, truncated or corrupt, for train-net and evaluate-net.

TINY = "[gen-configs]\nd_xy_points = 4\nc_xy_points = 4\nc_z_points = 3\ns_xy_points = 6\ns_z_points = 3\n"


@case("train_net_without_a_validation_set_prints_no_nan", needs=("gen-configs", "train-net"))
def _(ctx):
    # --validation_fraction 0: no validation patterns. The progress line said "val nan (best inf @0)" and the
    # summary "validation nan"; now "no validation set", and --patience, which has nothing to act on, is named.
    data = make_dataset(ctx)
    out, err = ctx.expect_success("train-net", ["--data", data, "--output", "net.h5", "--epochs", "3",
                                                "--train_count", "20", "--validation_fraction", "0",
                                                "--patience", "2"])
    if re.search(r"\bnan\b|\binf\b", out + err, re.IGNORECASE):
        raise Failure(f"a NaN or inf printed:\n{out}\n{err}")
    if "no validation set" not in out or "--patience has nothing to act on" not in err:
        raise Failure(f"the missing validation set is not said:\n{out}\n{err}")


def make_dataset(ctx, name="data.h5"):
    ctx.write("tiny.toml", TINY)
    ctx.expect_success("gen-configs", ["--config", "tiny.toml", "--output", name, "--quiet"])
    os.remove(ctx.path(name + ".config.toml"))
    os.remove(ctx.path("tiny.toml"))
    return name


def make_network(ctx, data, name="net.h5"):
    ctx.expect_success("train-net", ["--data", data, "--output", name, "--epochs", "3", "--train_count", "20",
                                     "--quiet"])
    os.remove(ctx.path(name + ".config.toml"))
    return name


def spoiled(ctx, source, name, how):
    with open(ctx.path(source), "rb") as f:
        data = bytearray(f.read())
    if how == "truncate":
        data = data[: len(data) // 2]
    elif how == "corrupt":
        for k in range(64, len(data), 37):
            data[k] ^= 0x5A
    ctx.write(name, bytes(data))
    return name


@case("train_net_data_is_a_network", needs=("gen-configs", "train-net"))
def _(ctx):
    net = make_network(ctx, make_dataset(ctx))
    ctx.expect_failure("train-net", ["--data", net, "--output", "out.h5", "--quiet"], 3,
                       r"^error: 'net\.h5' is a contactnn-network file, expected a contactnn-dataset file")


@case("train_net_data_truncated", needs=("gen-configs", "train-net"))
def _(ctx):
    bad = spoiled(ctx, make_dataset(ctx), "half.h5", "truncate")
    ctx.expect_failure("train-net", ["--data", bad, "--output", "out.h5", "--quiet"], 3, r"^error: .*'half\.h5'")


@case("train_net_data_corrupt", needs=("gen-configs", "train-net"))
def _(ctx):
    bad = spoiled(ctx, make_dataset(ctx), "corrupt.h5", "corrupt")
    ctx.expect_failure("train-net", ["--data", bad, "--output", "out.h5", "--quiet"], 3, r"^error: .*'corrupt\.h5'")


@case("train_net_data_is_csv", needs=("gen-configs", "train-net"))
def _(ctx):
    ctx.write("data.h5", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("train-net", ["--data", "data.h5", "--output", "out.h5", "--quiet"], 3,
                       r"^error: 'data\.h5' is not an HDF5 file")


@case("evaluate_net_weights_is_a_dataset", needs=("gen-configs", "evaluate-net"))
def _(ctx):
    data = make_dataset(ctx)
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("evaluate-net", ["--weights", data, "--input", src, "--output", "pred.csv"], 3,
                       r"^error: 'data\.h5' is a contactnn-dataset file, expected a contactnn-network file")


@case("evaluate_net_weights_truncated", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    bad = spoiled(ctx, make_network(ctx, make_dataset(ctx)), "half.h5", "truncate")
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("evaluate-net", ["--weights", bad, "--input", src, "--output", "pred.csv"], 3,
                       r"^error: .*'half\.h5'")


@case("evaluate_net_bad_csv", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    net = make_network(ctx, make_dataset(ctx))
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4\n")
    ctx.expect_failure("evaluate-net", ["--weights", net, "--input", src, "--output", "pred.csv"], 3,
                       r"in\.csv':3: ragged row: 14 fields, the header has 15")


@case("evaluate_net_data_is_a_network", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    net = make_network(ctx, make_dataset(ctx))
    ctx.expect_failure("evaluate-net", ["--weights", net, "--data", net, "--report", "rep", "--quiet"], 3,
                       r"^error: 'net\.h5' is a contactnn-network file, expected a contactnn-dataset file")


@case("evaluate_net_two_sets_named_alike", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    # Sets are named by their file stems in every table: two files data.h5 in different folders gave two
    # blocks named 'data' (networks named alike were already refused).
    data = make_dataset(ctx)
    net = make_network(ctx, data)
    os.makedirs(ctx.path("other"))
    shutil.copy(ctx.path(data), ctx.path("other/data.h5"))
    ctx.expect_failure("evaluate-net", ["--weights", net, "--data", data, "--data", "other/data.h5", "--report",
                                        "rep", "--quiet"], 2,
                       r"^error: two sets named 'data' \(data\.h5, other/data\.h5\)")


# ------------------------------------------------------------------------------------------------------
# Issue 12. Messages: a malformed field is quoted short; other encodings and line ends are named.

@case("csv_huge_field_quoted_short")
def _(ctx):
    huge = "7" * 5_000_000 + "x" * 5_000_000
    label(ctx, f"{HEADER}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,{huge},0.1\n", 3,
          r"^error: '[^']*in\.csv':2: column 'sy': '7{40}\.\.\.' \(10000000 bytes\) is not a number\n$")


# ------------------------------------------------------------------------------------------------------
# Issue 12. Values beyond their type are range errors, not wrapped or saturated.

@case("seed_negative")
def _(ctx):
    ctx.expect_failure("gen-configs", ["--output", "out.h5", "--seed", "-1"], 2,
                       r"^--seed: must be an integer in 0\.\.9223372036854775807, got '-1'")


@case("seed_beyond_64_bits")
def _(ctx):
    ctx.expect_failure("gen-configs", ["--output", "out.h5", "--seed", "99999999999999999999"], 2,
                       r"^--seed: must be an integer in 0\.\.9223372036854775807, got '99999999999999999999'")


@case("count_beyond_int")
def _(ctx):
    ctx.expect_failure("gen-configs", ["--output", "out.h5", "--d_xy_points", "4000000000"], 2,
                       r"^--d_xy_points: must be an integer in 1\.\.400, got '4000000000'")


@case("threads_upper_bound")
def _(ctx):
    ctx.expect_failure("gen-configs", ["--output", "out.h5", "--threads", "100000"], 2,
                       r"^--threads: must be an integer in 0\.\.1024, got '100000'")


@case("train_count_not_an_integer", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    for value in ("1e30", "-5", "2.5"):
        ctx.expect_failure("train-net", ["--data", data, "--output", "net.h5", "--train_count", value], 2,
                           r"^--train_count: must be an integer in 1\.\.4294967295, got '" + re.escape(value) + "'")


@case("train_count_above_the_ok_rows", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    ctx.expect_failure("train-net", ["--data", data, "--output", "net.h5", "--train_count", "100000", "--quiet"], 2,
                       r"^error: --train_count 100000 and --validation_fraction 0\.2 need 120000 rows with status ok; "
                       r"'data\.h5' has \d+\n$")


@case("train_net_target_low_above_high", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    ctx.expect_failure("train-net", ["--data", data, "--output", "net.h5", "--target_low", "0.9", "--target_high",
                                     "0.1"], 2, r"^error: --target_low 0\.9 and --target_high 0\.1: expected 0 < ")


@case("train_net_bad_hidden", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    ctx.expect_failure("train-net", ["--data", data, "--output", "net.h5", "--hidden", "8,x"], 2,
                       r"^error: --hidden: expected comma-separated layer sizes in 1\.\.4096, got '8,x'\n$")


@case("out_of_memory_is_a_resource_error", needs=("gen-configs", "train-net"))
def _(ctx):
    # Three 4096-wide layers need well over a gigabyte; the address space is limited to 700 MB.
    data = make_dataset(ctx)

    def limit_memory():
        resource.setrlimit(resource.RLIMIT_AS, (700 << 20, 700 << 20))

    ctx.expect_failure("train-net", ["--data", data, "--output", "net.h5", "--hidden", "4096,4096,4096", "--epochs",
                                     "1", "--train_count", "20", "--quiet"], 4,
                       r"^error: out of memory: the system refused an allocation", env={"OMP_NUM_THREADS": "1"},
                       preexec_fn=limit_memory)


# ------------------------------------------------------------------------------------------------------
# Issue 12. Outputs that are not regular files are written in place, never replaced.

def is_char_device(path):
    return stat.S_ISCHR(os.stat(path).st_mode)


def tiny_config(ctx):
    ctx.write("c.toml", "[gen-configs]\nd_xy_points = 2\nc_xy_points = 2\ns_xy_points = 3\nquiet = true\n")
    return "c.toml"


@case("output_dev_null_label_mode")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_success("gen-configs", ["--input", src, "--output", "/dev/null"])
    if not is_char_device("/dev/null"):
        raise Failure("/dev/null was replaced by a regular file")
    if sorted(os.listdir(ctx.dir)) != ["in.csv"]:
        raise Failure(f"files left: {sorted(os.listdir(ctx.dir))}")


@case("output_dev_null_enumeration")
def _(ctx):
    # HDF5 needs a seekable file: a temporary in $TMPDIR, copied into the device, then removed. No
    # /dev/null.config.toml: an output written in place has no "beside".
    os.mkdir(ctx.path("tmp"))
    ctx.expect_success("gen-configs", ["--config", tiny_config(ctx), "--output", "/dev/null"],
                       env={"TMPDIR": ctx.path("tmp")})
    if not is_char_device("/dev/null"):
        raise Failure("/dev/null was replaced by a regular file")
    if os.path.exists("/dev/null.config.toml") or os.listdir(ctx.path("tmp")):
        raise Failure(f"left behind: /dev/null.config.toml or {os.listdir(ctx.path('tmp'))}")


def read_fifo_while(ctx, fifo, run):
    """Reads the FIFO in a thread while `run()` writes it; returns the bytes read."""
    got = []

    def reader():
        with open(fifo, "rb") as f:
            got.append(f.read())

    t = threading.Thread(target=reader)
    t.start()
    try:
        run()
    finally:
        if t.is_alive():  # the tool never opened it: unblock the reader
            try:
                os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
            except OSError:
                pass
        t.join(60)
    if not stat.S_ISFIFO(os.stat(fifo).st_mode):
        raise Failure("the FIFO was replaced by a regular file")
    return got[0] if got else b""


@case("output_fifo_label_and_enumeration")
def _(ctx):
    src = ctx.write("in.csv", f"id,{HEADER}\n1,{ROW}\n2,{ROW}\n")
    ctx.expect_success("gen-configs", ["--input", src, "--output", "ref.csv"])
    ctx.expect_success("gen-configs", ["--config", tiny_config(ctx), "--output", "ref.h5"])
    os.mkfifo(ctx.path("out.fifo"))
    for args, ref in ((["--input", src], "ref.csv"), (["--config", "c.toml"], "ref.h5")):
        got = read_fifo_while(ctx, ctx.path("out.fifo"),
                              lambda: ctx.expect_success("gen-configs", args + ["--output", "out.fifo"]))
        with open(ctx.path(ref), "rb") as f:
            if got != f.read():
                raise Failure(f"the FIFO received {len(got)} bytes, not those of {ref}")
    if sorted(os.listdir(ctx.dir)) != ["c.toml", "in.csv", "out.fifo", "ref.csv", "ref.h5", "ref.h5.config.toml"]:
        raise Failure(f"files left: {sorted(os.listdir(ctx.dir))}")


@case("output_dev_stdout")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_success("gen-configs", ["--input", src, "--output", "ref.csv"])
    out, _ = ctx.expect_success("gen-configs", ["--input", src, "--output", "/dev/stdout"], raw=True)
    with open(ctx.path("ref.csv"), "rb") as f:
        if out != f.read():
            raise Failure(f"stdout got {out!r}")
    if sorted(os.listdir(ctx.dir)) != ["in.csv", "ref.csv"]:
        raise Failure(f"files left: {sorted(os.listdir(ctx.dir))}")


@case("output_symlinks_are_followed_never_replaced")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_success("gen-configs", ["--input", src, "--output", "ref.csv"])
    os.mkdir(ctx.path("real"))
    ctx.write("real/target.csv", "old\n")
    os.symlink("real/target.csv", ctx.path("link.csv"))
    os.symlink("/dev/null", ctx.path("null.csv"))
    for link in ("link.csv", "null.csv"):
        ctx.expect_success("gen-configs", ["--input", src, "--output", link])
        if not os.path.islink(ctx.path(link)):
            raise Failure(f"{link} was replaced by a regular file")
    with open(ctx.path("real/target.csv"), "rb") as a, open(ctx.path("ref.csv"), "rb") as b:
        if a.read() != b.read():
            raise Failure("the link's target does not hold the output")
    if not is_char_device("/dev/null"):
        raise Failure("/dev/null was replaced by a regular file")


# ------------------------------------------------------------------------------------------------------
# Issue 12. An output that is an input, however spelled, is refused before any work.

@case("gen_configs_output_is_input")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("gen-configs", ["--input", src, "--output", "./in.csv"], 2,
                       r"^error: --output '\./in\.csv' and --input '[^']*in\.csv' are the same file: refusing to "
                       r"overwrite an input\n$")


@case("gen_configs_output_is_config")
def _(ctx):
    tiny_config(ctx)
    ctx.expect_failure("gen-configs", ["--config", "c.toml", "--output", "c.toml"], 2,
                       r"^error: --output 'c\.toml' and --config 'c\.toml' are the same file")


def train_identity_case(ctx, prepare, args, pattern):
    data = make_dataset(ctx)
    prepare(data)
    ctx.expect_failure("train-net", args + ["--epochs", "5", "--train_count", "20", "--quiet"], 2, pattern)


@case("train_net_output_is_data", needs=("gen-configs", "train-net"))
def _(ctx):
    for spelling in ("data.h5", "./data.h5", "sub/../data.h5"):
        os.makedirs(ctx.path("sub"), exist_ok=True)
        train_identity_case(ctx, lambda d: None, ["--data", "data.h5", "--output", spelling],
                            r"^error: --output '" + re.escape(spelling) + r"' and --data 'data\.h5' are the same file: "
                            r"refusing to overwrite an input\n$")
        os.remove(ctx.path("data.h5"))


@case("train_net_output_links_to_data", needs=("gen-configs", "train-net"))
def _(ctx):
    train_identity_case(ctx, lambda d: os.symlink(d, ctx.path("soft.h5")), ["--data", "data.h5", "--output", "soft.h5"],
                        r"^error: --output 'soft\.h5' and --data 'data\.h5' are the same file")
    os.remove(ctx.path("soft.h5"))
    os.link(ctx.path("data.h5"), ctx.path("hard.h5"))
    ctx.expect_failure("train-net", ["--data", "data.h5", "--output", "hard.h5", "--quiet"], 2,
                       r"^error: --output 'hard\.h5' and --data 'data\.h5' are the same file")


@case("train_net_header_or_checkpoint_is_data", needs=("gen-configs", "train-net"))
def _(ctx):
    train_identity_case(ctx, lambda d: None, ["--data", "data.h5", "--output", "net.h5", "--export-header", "data.h5"],
                        r"^error: --export-header 'data\.h5' and --data 'data\.h5' are the same file")
    os.rename(ctx.path("data.h5"), ctx.path("net.h5.checkpoint.h5"))
    ctx.expect_failure("train-net", ["--data", "net.h5.checkpoint.h5", "--output", "net.h5", "--checkpoint-every", "2",
                                     "--quiet"], 2,
                       r"^error: the checkpoint 'net\.h5\.checkpoint\.h5' and --data 'net\.h5\.checkpoint\.h5' are the "
                       r"same file")


@case("train_net_header_is_output", needs=("gen-configs", "train-net"))
def _(ctx):
    train_identity_case(ctx, lambda d: None, ["--data", "data.h5", "--output", "net.h5", "--export-header", "./net.h5"],
                        r"^error: --output 'net\.h5' and --export-header '\./net\.h5' are the same file: one output "
                        r"would overwrite the other\n$")


@case("evaluate_net_output_is_an_input", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    net = make_network(ctx, make_dataset(ctx))
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("evaluate-net", ["--weights", net, "--input", src, "--output", "./net.h5"], 2,
                       r"^error: --output '\./net\.h5' and --weights 'net\.h5' are the same file")
    ctx.expect_failure("evaluate-net", ["--weights", net, "--input", "in.csv", "--output", "in.csv"], 2,
                       r"^error: --output 'in\.csv' and --input 'in\.csv' are the same file")


@case("evaluate_net_report_holds_an_input", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    data = make_dataset(ctx)
    net = make_network(ctx, data)
    os.mkdir(ctx.path("rep"))
    os.rename(ctx.path(data), ctx.path("rep/data.h5"))
    ctx.expect_failure("evaluate-net", ["--weights", net, "--data", "rep/data.h5", "--report", "rep", "--quiet"], 2,
                       r"^error: --report 'rep' holds --data 'rep/data\.h5': the directory is replaced whole")
    os.rename(ctx.path("rep/data.h5"), ctx.path("rep/report.md"))
    ctx.expect_failure("evaluate-net", ["--weights", net, "--data", "rep/report.md", "--report", "rep", "--quiet"], 2,
                       r"^error: --report 'rep' holds --data 'rep/report\.md': the directory is replaced whole")


# ------------------------------------------------------------------------------------------------------
# Issue 12, doubtful cases: what can be checked before the first epoch is; a report is replaced whole.

@case("train_net_header_is_a_directory", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    os.mkdir(ctx.path("net.h"))
    # A checkpoint every epoch proves that no epoch ran.
    ctx.expect_failure("train-net", ["--data", data, "--output", "net.h5", "--export-header", "net.h", "--epochs",
                                     "100000", "--checkpoint-every", "1", "--train_count", "20", "--quiet"], 4,
                       r"^error: --export-header: cannot write 'net\.h': it is a directory\n$")


@case("train_net_output_directory_missing", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    ctx.expect_failure("train-net", ["--data", data, "--output", "no/dir/net.h5", "--train_count", "20", "--quiet"], 4,
                       r"^error: --output: cannot write 'no/dir/net\.h5': directory 'no/dir' does not exist\n$")


@case("train_net_checkpoint_needs_a_regular_output", needs=("gen-configs", "train-net"))
def _(ctx):
    data = make_dataset(ctx)
    ctx.expect_failure("train-net", ["--data", data, "--output", "/dev/null", "--checkpoint-every", "5",
                                     "--train_count", "20", "--quiet"], 2,
                       r"^error: --checkpoint-every and --resume need --output to name a file")


@case("report_over_an_empty_dataset", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    net = make_network(ctx, make_dataset(ctx))
    ctx.write("none.toml", "[gen-configs]\nd_xy_points = 10\nc_xy_points = 2\ns_xy_points = 2\nquiet = true\n")
    out, _ = ctx.expect_success("gen-configs", ["--config", "none.toml", "--output", "empty.h5"])
    if not re.search(r"written +0 ", out):
        raise Failure(f"expected an empty dataset:\n{out}")
    ctx.expect_failure("evaluate-net", ["--weights", net, "--data", "empty.h5", "--report", "rep", "--quiet"], 3,
                       r"^error: 'empty\.h5' holds 0 configurations and none with status ok: nothing to report")


@case("report_replaced_whole", needs=("gen-configs", "train-net", "evaluate-net"))
def _(ctx):
    data = make_dataset(ctx)
    net = make_network(ctx, data)
    args = ["--weights", net, "--data", data, "--report", "rep", "--quiet", "--timing", "false"]
    ctx.expect_success("evaluate-net", args)
    first = sorted(os.listdir(ctx.path("rep")))
    if "report.md" not in first or "evaluate-net.config.toml" not in first or "speed.csv" in first:
        raise Failure(f"unexpected report files {first}")
    ctx.write("rep/speed.csv", "a stale file of an earlier report\n")
    before = os.stat(ctx.path("rep")).st_ino
    ctx.expect_success("evaluate-net", args)
    if sorted(os.listdir(ctx.path("rep"))) != first:
        raise Failure(f"the report was not replaced whole: {sorted(os.listdir(ctx.path('rep')))}")
    if os.stat(ctx.path("rep")).st_ino == before:
        raise Failure("the report directory was rewritten in place")
    if sorted(os.listdir(ctx.dir)) != ["data.h5", "net.h5", "rep"]:
        raise Failure(f"files left beside the report: {sorted(os.listdir(ctx.dir))}")


@case("two_runs_one_output_leave_a_matching_pair")
def _(ctx):
    # Two runs with different settings writing the same output at the same time: the dataset and its
    # effective config must come from the same run (they are committed together under a directory lock).
    configs = {}
    for name, points in (("a", 5), ("b", 6)):
        ctx.write(f"{name}.toml", f"[gen-configs]\nd_xy_points = {points}\nc_xy_points = 4\ns_xy_points = 5\n"
                                  f"quiet = true\n")
        ctx.expect_success("gen-configs", ["--config", f"{name}.toml", "--output", f"ref-{name}.h5"])
        with open(ctx.path(f"ref-{name}.h5"), "rb") as f:
            configs[name] = f.read()
    for trial in range(6):
        procs = [subprocess.Popen([ctx.tools["gen-configs"], "--config", f"{n}.toml", "--output", "out.h5"],
                                  cwd=ctx.dir, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) for n in "ab"]
        if any(p.wait(120) != 0 for p in procs):
            raise Failure(f"trial {trial}: a run failed")
        with open(ctx.path("out.h5"), "rb") as f:
            data = f.read()
        with open(ctx.path("out.h5.config.toml")) as f:
            points = re.search(r"\nd_xy_points=(\d+)\n", f.read()).group(1)
        expected = configs["a" if points == "5" else "b"]
        if data != expected:
            raise Failure(f"trial {trial}: out.h5.config.toml says d_xy_points={points} but out.h5 is the other run's")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--gen-configs", dest="gen_configs")
    parser.add_argument("--train-net", dest="train_net")
    parser.add_argument("--evaluate-net", dest="evaluate_net")
    parser.add_argument("--work", default="bad-inputs")
    parser.add_argument("--case", action="append", default=[])
    parser.add_argument("--all", action="store_true")
    parser.add_argument("--list", action="store_true")
    a = parser.parse_args()
    tools = {k: os.path.abspath(v) for k, v in {"gen-configs": a.gen_configs, "train-net": a.train_net,
                                                "evaluate-net": a.evaluate_net}.items() if v}
    runnable = [n for n, (_, needs) in CASES.items() if all(t in tools for t in needs)]
    if a.list:
        print(";".join(runnable))
        return 0
    return CASES.run(runnable if a.all else a.case, a.work, lambda directory: Context(tools, directory))


if __name__ == "__main__":
    sys.exit(main())
