"""The provenance block and the atomic write of a results/ page (imported by the scripts that write one).

Every page under results/ that a script writes says when and where its numbers were made: the date, the
commit (with "+ local changes" when the working tree differs from it), the machine (CPU model and core count),
the load average (other work on the same cores inflates times) and the exact command line. Take the
provenance at the start of the run (before any output changes the tree), the load again at the end:

  page = results_page.Provenance("scripts/frontier", sys.argv[1:])   # at the start
  ...
  text = [f"# Title", ""] + page.lines(seconds=...) + [...]
  results_page.write(path, "\\n".join(text) + "\\n")                   # temp file, then os.replace
"""
import datetime
import os
import shlex
import subprocess
import textwrap

import script_checks

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cpu_model():
    """The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def commit():
    """`git rev-parse --short HEAD`, with " + local changes" when tracked or untracked (not ignored) files differ
    from it; "not a git checkout" where git cannot tell."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
        if head.returncode != 0:
            return "not a git checkout"
        dirty = subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True, text=True)
    except OSError:
        return "not a git checkout (no git)"
    text = head.stdout.strip()
    if dirty.returncode != 0 or dirty.stdout.strip():
        text += " + local changes"
    return text


def load():
    try:
        return os.getloadavg()
    except OSError:
        return None


def load_text(values):
    return "unknown" if values is None else " / ".join(f"{v:.2f}" for v in values)


class Provenance:
    """Date, commit, machine and load taken when made; lines() adds the load at the time of writing."""

    def __init__(self, script, argv, cwd=None):
        self.command = " ".join([script] + [shlex.quote(x) for x in argv])
        self.cwd = os.path.abspath(cwd or os.getcwd())
        self.started = datetime.datetime.now(datetime.timezone.utc)
        self.commit = commit()
        self.cpu = cpu_model()
        self.cores = os.cpu_count() or 0
        self.load_start = load()

    def lines(self, seconds=None):
        """The page's provenance block (Markdown list items)."""
        end = load()
        took = "" if seconds is None else f" ({seconds:.0f} s)"
        where = "the repository root" if self.cwd == ROOT else f"`{self.cwd}`"
        return [f"- **Command**: `{self.command}`{took}, run from {where}.",
                f"- **Run**: {self.started.strftime('%Y-%m-%d %H:%M')} UTC, commit {self.commit}.",
                f"- **Machine**: {self.cpu}, {self.cores} cores; load average (1 / 5 / 15 min) "
                f"{load_text(self.load_start)} at the start, {load_text(end)} at the end"
                + (": other work shared the cores, so times are inflated; compare ratios within the run."
                   if self.loaded(end) else ".")]

    def loaded(self, end=None):
        """Whether the 1-minute load average went above the core count during the run."""
        values = [v[0] for v in (self.load_start, end if end is not None else load()) if v is not None]
        return bool(values) and max(values) > max(self.cores, 1)


def check_writable(parser, flag, path, shown=None):
    """parser.error (exit 2) naming `flag` and `path` (or `shown`, the path as the caller wrote it) unless a file
    can be written at `path`: its folder is made and a file written and removed in it; an existing directory of
    that name is refused."""
    script_checks.output_file(parser, flag, path, path if shown is None else shown)


def wrap(text, width=118):
    """Wraps the prose of a Markdown text at `width` (list items with a two-space hang); tables, headings, code
    blocks and short lines are left as they are."""
    out, code = [], False
    for line in text.split("\n"):
        if line.startswith("```"):
            code = not code
        if code or line.startswith(("```", "|", "#", "    ")) or len(line) <= width:
            out.append(line)
            continue
        hang = "  " if line.startswith(("- ", "* ")) else ""
        out += textwrap.wrap(line, width=width, subsequent_indent=hang, break_long_words=False,
                             break_on_hyphens=False)
    return "\n".join(out)


def write(path, text):
    """Writes `text` to `path` atomically: a temporary file in the same directory, then os.replace."""
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    tmp = os.path.join(directory, f".{os.path.basename(path)}.{os.getpid()}.tmp")
    try:
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def kept_sections(path, marker):
    """The part of an existing page from the line `marker` on (sections that other commands made, kept as they
    are when the script rewrites the rest); "" when the page or the marker is absent."""
    try:
        with open(path) as f:
            text = f.read()
    except OSError:
        return ""
    at = text.find("\n" + marker + "\n")
    return text[at + 1:] if at >= 0 else ""
