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
import shutil
import subprocess
import sys

HEADER = "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz"
ROW = "0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,0.1"
NORMALS = "nax,nay,naz,nbx,nby,nbz,ncx,ncy,ncz,ndx,ndy,ndz"

CASES = {}


def case(name, needs=("gen-configs",)):
    def register(function):
        CASES[name] = (function, needs)
        return function
    return register


class Failure(Exception):
    pass


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

    def run(self, tool, args, timeout=120):
        command = [self.tools[tool]] + args
        try:
            p = subprocess.run(command, cwd=self.dir, capture_output=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise Failure(f"hang: {' '.join(command)} ran past {timeout} s")
        return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")

    def expect_failure(self, tool, args, code, pattern, outputs=()):
        """Runs a command that must fail with `code`, a stderr matching `pattern`, and leave nothing behind."""
        before = snapshot(self.dir)
        rc, out, err = self.run(tool, args)
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

    def expect_success(self, tool, args):
        rc, out, err = self.run(tool, args)
        if rc != 0:
            raise Failure(f"exit status {rc}, expected 0\ncommand: {tool} {' '.join(args)}\nstderr:\n{err}")
        return out, err


def snapshot(directory):
    """Every file under `directory` with its size and content hash."""
    result = {}
    for root, _, files in os.walk(directory):
        for name in files:
            full = os.path.join(root, name)
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


@case("csv_text_in_number")
def _(ctx):
    label(ctx, f"{HEADER}\n{ROW}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,abc,0.1\n", 3,
          r"^error: '[^']*in\.csv':3: column 'sy': 'abc' is not a number\n$")


@case("csv_empty_field")
def _(ctx):
    label(ctx, f"{HEADER}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,\n", 3, r"in\.csv':2: column 'sz': '' is not a number")


@case("csv_missing_column")
def _(ctx):
    label(ctx, "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4\n", 3,
          r"in\.csv':1: missing column 'sz'")


@case("csv_ragged_row_short")
def _(ctx):
    label(ctx, f"{HEADER}\n{ROW}\n{ROW}\n0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4\n", 3,
          r"in\.csv':4: ragged row: 14 fields, the header has 15")


@case("csv_ragged_row_long")
def _(ctx):
    label(ctx, f"{HEADER}\n{ROW},7\n", 3, r"in\.csv':2: ragged row: 16 fields, the header has 15")


@case("csv_empty_file")
def _(ctx):
    label(ctx, "", 3, r"in\.csv': empty file: expected a header row and data rows")


@case("csv_blank_lines_only")
def _(ctx):
    label(ctx, "\n  \n\r\n", 3, r"in\.csv': empty file")


@case("csv_header_only")
def _(ctx):
    label(ctx, f"{HEADER}\n", 3, r"in\.csv': header only: expected at least one data row")


@case("csv_duplicate_column")
def _(ctx):
    label(ctx, f"{HEADER},ax\n{ROW},0\n", 3, r"in\.csv':1: duplicate column 'ax' in the header")


@case("csv_empty_column_name")
def _(ctx):
    label(ctx, f"{HEADER},\n{ROW},x\n", 3, r"in\.csv':1: empty column name in the header")


@case("csv_unterminated_quote")
def _(ctx):
    label(ctx, f"{HEADER},note\n{ROW},fine\n{ROW},\"never closed\n{ROW},x\n", 3,
          r"in\.csv':3: unterminated quoted field")


@case("csv_binary_garbage")
def _(ctx):
    label(ctx, bytes(range(256)) * 4, 3, r"^error: '[^']*in\.csv'")


@case("csv_gregory_without_normal_columns")
def _(ctx):
    label(ctx, f"{HEADER}\n{ROW}\n", 3, r"in\.csv':1: missing column 'nax'", surface="gregory")


@case("input_file_missing")
def _(ctx):
    label(ctx, None, 2, r"--input: File does not exist: .*in\.csv")


@case("input_is_a_directory")
def _(ctx):
    os.mkdir(ctx.path("in.csv"))
    label(ctx, None, 2, r"--input: .*in\.csv")


@case("output_directory_missing")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    ctx.expect_failure("gen-configs", ["--input", src, "--output", "no/such/dir/out.csv"], 4,
                       r"^error: cannot write 'no/such/dir/out\.csv': directory 'no/such/dir' does not exist\n$")


@case("output_is_a_directory")
def _(ctx):
    src = ctx.write("in.csv", f"{HEADER}\n{ROW}\n")
    os.mkdir(ctx.path("out.csv"))
    ctx.write("out.csv/keep", "x")
    ctx.expect_failure("gen-configs", ["--input", src, "--output", "out.csv"], 4,
                       r"^error: cannot write 'out\.csv': it is a directory\n$")


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


# ------------------------------------------------------------------------------------------------------
# Config files and option values (enumeration mode). Message: config file 'F', line N, key K.

def config(ctx, text, code, pattern, extra=()):
    ctx.write("c.toml", text)
    ctx.expect_failure("gen-configs", ["--config", "c.toml", "--output", "out.h5", "--quiet"] + list(extra), code,
                       pattern, outputs=["out.h5", "out.h5.config.toml"])


@case("config_unknown_key")
def _(ctx):
    config(ctx, "[gen-configs]\nd_xy_points = 4\nd_xy_pionts = 4\n", 2,
           r"^error: config file 'c\.toml': line 3: unknown key 'd_xy_pionts' in \[gen-configs\] "
           r"\(expected one of: [^)]*d_xy_points")


@case("config_unknown_section")
def _(ctx):
    config(ctx, "[gen-configs]\nd_xy_points = 4\n[gen-config]\nc_xy_points = 4\n", 2,
           r"^error: config file 'c\.toml': line 3: unknown section \[gen-config\] \(expected one of")


@case("config_malformed_section_header")
def _(ctx):
    config(ctx, "[gen-configs\nd_xy_points = 4\n", 2,
           r"^error: config file 'c\.toml': line 1, column \d+: not valid TOML: .*table header")


@case("config_key_outside_any_section")
def _(ctx):
    config(ctx, "# a study\nd_xy_points = 4\n[gen-configs]\n", 2,
           r"^error: config file 'c\.toml': line 2: key 'd_xy_points' is outside any section")


@case("config_value_out_of_range")
def _(ctx):
    config(ctx, "[gen-configs]\n\nd_xy_points = 0\n", 2,
           r"^error: config file 'c\.toml', line 3, key 'd_xy_points': --d_xy_points: must be an integer in 1\.\.400, "
           r"got '0'\n$")


@case("config_negative_limit")
def _(ctx):
    config(ctx, "[gen-configs]\nz_limit = -0.3\n", 2,
           r"^error: config file 'c\.toml', line 2, key 'z_limit': --z_limit: must be a finite number > 0, got -0\.3\n$")


@case("config_wrong_type")
def _(ctx):
    config(ctx, "[gen-configs]\nconvex = \"maybe\"\n", 2,
           r"^error: config file 'c\.toml', line 2, key 'convex': expected a boolean \(true or false\), got a string\n$")


@case("config_bare_word_is_not_toml")
def _(ctx):
    config(ctx, "[gen-configs]\nconvex = maybe\n", 2, r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML")


@case("config_string_for_an_integer")
def _(ctx):
    config(ctx, "[gen-configs]\n\nd_xy_points = \"4\"\n", 2,
           r"^error: config file 'c\.toml', line 3, key 'd_xy_points': expected an integer, got a string\n$")


@case("config_float_for_an_integer")
def _(ctx):
    config(ctx, "[gen-configs]\nd_xy_points = 4.5\n", 2,
           r"^error: config file 'c\.toml', line 2, key 'd_xy_points': expected an integer, got a floating-point number")


@case("config_duplicate_key")
def _(ctx):
    # Issue 12: the reader kept the first value and dropped the second silently.
    config(ctx, "[gen-configs]\nd_xy_points = 8\nd_xy_points = 9\n", 2,
           r"^error: config file 'c\.toml': line 3, column \d+: not valid TOML: .*redefine.*'d_xy_points'")


@case("config_duplicate_section")
def _(ctx):
    config(ctx, "[gen-configs]\nd_xy_points = 8\n[train-net]\n[gen-configs]\nc_xy_points = 9\n", 2,
           r"^error: config file 'c\.toml': line 4, column \d+: not valid TOML: .*gen-configs")


@case("config_nested_table")
def _(ctx):
    config(ctx, "[gen-configs.grid]\nd_xy_points = 8\n", 2,
           r"^error: config file 'c\.toml': line 1: unknown key 'grid' in \[gen-configs\]")


@case("config_array_of_tables")
def _(ctx):
    config(ctx, "[[gen-configs]]\nd_xy_points = 8\n", 2,
           r"^error: config file 'c\.toml': line 1: \[\[gen-configs\]\] is an array of tables")


@case("config_infinite_limit")
def _(ctx):
    config(ctx, "[gen-configs]\nxy_limit = inf\n", 2,
           r"^error: config file 'c\.toml', line 2, key 'xy_limit': --xy_limit: must be a finite number > 0, got inf\n$")


@case("config_min_angle_above_max")
def _(ctx):
    config(ctx, "[gen-configs]\nmin_angle_degrees = 100\nmax_angle_degrees = 90\n", 2,
           r"^error: min_angle_degrees 100 is above max_angle_degrees 90: no segment could pass\n$")


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


@case("config_bad_choice")
def _(ctx):
    config(ctx, "[gen-configs]\nsurface = \"quad\"\n", 2,
           r"^error: config file 'c\.toml', line 2, key 'surface': --surface: quad not in")


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


@case("config_unterminated_string")
def _(ctx):
    config(ctx, "[gen-configs]\noutput = \"never closed\n", 2,
           r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML: .*string")


@case("config_two_values")
def _(ctx):
    config(ctx, "[gen-configs]\nd_xy_points = 4 5\n", 2, r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML")


@case("config_text_after_string")
def _(ctx):
    config(ctx, "[gen-configs]\nsurface = \"bilinear\" x\n", 2,
           r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML: .*saw 'x'")


@case("config_line_without_value")
def _(ctx):
    config(ctx, "[gen-configs]\nquiet\n", 2, r"^error: config file 'c\.toml': line 2, column \d+: not valid TOML: .*expected '='")


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
    names = runnable if a.all else a.case
    failed = 0
    for name in names:
        if name not in CASES:
            print(f"unknown case {name}", file=sys.stderr)
            return 2
        directory = os.path.abspath(os.path.join(a.work, name))
        shutil.rmtree(directory, ignore_errors=True)
        os.makedirs(directory)
        try:
            CASES[name][0](Context(tools, directory))
            print(f"PASS {name}")
        except Failure as e:
            failed += 1
            print(f"FAIL {name}\n{e}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
