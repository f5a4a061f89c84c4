"""Option checks shared by the scripts under scripts/ (imported, not run).

Every script checks every option before any work: a value out of range, a missing input or an output that
cannot be written is one line on stderr and exit status 2 (argparse's own usage errors), never a Python
traceback and never minutes of work first. The ranges are the apps' own where an option is passed on to one
(apps/common/cli_support.hpp: --threads 0..1024, --seed 0..2^63-1).

  p.add_argument("--count", type=integer(100), default=60000)
  p.add_argument("--target", type=real(0.0, lo_open=True))
  p.add_argument("--sizes", type=integer_list(1, 4096))
  a = p.parse_args()
  output_directory(p, "--output", a.output)        # made, and a file written and removed in it
  run_main("scene-study", main)                    # an OSError later: one line, exit 1, not a traceback
"""
import argparse
import math
import os
import sys
import tempfile

MAX_THREADS = 1024      # the apps' --threads limit (cli::kMaxThreads, CONTACTNN_MAX_THREADS)
MAX_SEED = 2**63 - 1    # the apps' --seed limit (a TOML integer)


def _integer_text(text):
    try:
        return int(text, 10)
    except (TypeError, ValueError):
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def integer(lo, hi=None):
    """An argparse type: a decimal integer in lo..hi (hi None: no upper end)."""
    def check(text):
        value = _integer_text(text)
        if value < lo or (hi is not None and value > hi):
            span = f"in {lo}..{hi}" if hi is not None else f">= {lo}"
            raise argparse.ArgumentTypeError(f"must be an integer {span}, got {text}")
        return value
    check.__name__ = "integer"
    return check


def real(lo=None, hi=None, lo_open=False, hi_open=False):
    """An argparse type: a finite number in [lo, hi] (an open end excludes the bound; None: no bound)."""
    def check(text):
        try:
            value = float(text)
        except (TypeError, ValueError):
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        below = lo is not None and (value <= lo if lo_open else value < lo)
        above = hi is not None and (value >= hi if hi_open else value > hi)
        if not math.isfinite(value) or below or above:
            bounds = []
            if lo is not None:
                bounds.append(("> " if lo_open else ">= ") + f"{lo:g}")
            if hi is not None:
                bounds.append(("< " if hi_open else "<= ") + f"{hi:g}")
            raise argparse.ArgumentTypeError(" ".join(["must be a finite number"] + [" and ".join(bounds)] * bool(bounds))
                                             + f", got {text}")
        return value
    check.__name__ = "number"
    return check


def integer_list(lo, hi=None, separator=","):
    """An argparse type: one or more integers in lo..hi separated by `separator` ("8,16,32")."""
    one = integer(lo, hi)

    def check(text):
        parts = text.split(separator) if separator != " " else text.split()
        if not parts or any(not p.strip() for p in parts):
            raise argparse.ArgumentTypeError(f"expected integers separated by {separator!r}, got {text!r}")
        try:
            return [one(p.strip()) for p in parts]
        except argparse.ArgumentTypeError as e:
            raise argparse.ArgumentTypeError(f"{text!r}: {e}") from None
    check.__name__ = "integer list"
    return check


def choice_list(choices, separator=","):
    """An argparse type: one or more of `choices` separated by `separator` ("bilinear,gregory")."""
    def check(text):
        parts = [p.strip() for p in text.split(separator)]
        wrong = [p for p in parts if p not in choices]
        if not parts or wrong:
            raise argparse.ArgumentTypeError(f"expected one or more of {', '.join(choices)} separated by "
                                             f"{separator!r}, got {text!r}")
        return parts
    check.__name__ = "choice list"
    return check


def existing_file(parser, flag, path):
    """parser.error (exit 2) unless `path` is a file that can be read."""
    if not os.path.isfile(path):
        parser.error(f"{flag} {path!r}: no such file")
    if not os.access(path, os.R_OK):
        parser.error(f"{flag} {path!r}: cannot be read")


def executables(parser, paths, hint):
    """parser.error (exit 2) naming the first of `paths` that is not an executable, with `hint` (how to build)."""
    for path in paths:
        if not os.access(path, os.X_OK) or os.path.isdir(path):
            parser.error(f"{path} not found: {hint}")


def output_directory(parser, flag, path, shown=None):
    """Makes directory `path` (and its parents) and writes and removes a file in it: parser.error (exit 2) naming
    `flag` and `path` (or `shown`) when it cannot (a read-only file system, a path under a file, no permission)."""
    try:
        os.makedirs(path, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".write-check-"):
            pass
    except OSError as e:
        parser.error(f"{flag} {path if shown is None else shown!r}: cannot write there ({e.strerror or e})")


def output_file(parser, flag, path, shown=None):
    """The same for a file to be written: its directory is made and checked, and an existing directory of that
    name is refused. The messages name `shown` where given (the path as the caller wrote it), else the path, and
    for a directory that cannot be written, that directory."""
    if os.path.isdir(path):
        parser.error(f"{flag} {path if shown is None else shown!r} is a directory, not a file")
    output_directory(parser, flag, os.path.dirname(os.path.abspath(path)), shown)


def run_main(name, main):
    """Runs main() and exits with its status; an OSError on the way (a disk that fills, an output made read-only
    after the checks) is one line on stderr and exit status 1, not a traceback."""
    try:
        status = main()
    except OSError as e:
        where = f" {e.filename!r}" if getattr(e, "filename", None) else ""
        print(f"{name}: error:{where} {e.strerror or e}", file=sys.stderr)
        status = 1
    except KeyboardInterrupt:
        print(f"{name}: interrupted", file=sys.stderr)
        status = 130
    sys.exit(status)
