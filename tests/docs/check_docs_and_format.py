#!/usr/bin/env python3
"""The docs list what the tree holds, and every C/C++ source is formatted by the repository's .clang-format.

  check_docs_and_format.py --root DIR [--clang-format PATH]

Fails (exit 1, one line per finding) when
  - a module of lib/ (a folder with a CMakeLists.txt) has no row in docs/library.md's module table
    ("## Modules and their dependencies"), or the table has a row for a module lib/ lacks;
  - a program of apps/ (a folder with a main.cpp) has no "## <name>" section in docs/tools.md, or tools.md has
    such a section for a program apps/ lacks;
  - `clang-format --dry-run -Werror` finds a C/C++ source (.c, .h, .cpp, .hpp) it would change.
Without clang-format (PATH empty or not executable) the format check is skipped with a message, not failed.
Exit 2 for a bad command line. tests/docs/fixture_test.py shows each failure on a tree of its own.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

SOURCE_SUFFIXES = (".c", ".h", ".cpp", ".hpp")
# A program's section: "## gen-configs". Sections of several words ("## The scripts") are not programs.
PROGRAM_HEADING = re.compile(r"^## ([a-z][a-z0-9-]*)\s*$")
MODULE_ROW = re.compile(r"^\| `([a-z][a-z0-9_]*)` \|")
MODULE_SECTION = "## Modules and their dependencies"


def folders_with(root, parent, marker, skip=()):
    base = os.path.join(root, parent)
    if not os.path.isdir(base):
        return set()
    return {name for name in os.listdir(base)
            if name not in skip and os.path.isfile(os.path.join(base, name, marker))}


def read_lines(path, problems):
    try:
        with open(path, encoding="utf-8") as f:
            return f.read().splitlines()
    except OSError as e:
        problems.append(f"{os.path.basename(path)}: cannot read {path}: {e.strerror}")
        return []


def module_rows(lines):
    """The first column of the module table in the section MODULE_SECTION (up to the next "## ")."""
    rows, inside = set(), False
    for line in lines:
        if line.startswith("## "):
            inside = line.strip() == MODULE_SECTION
        elif inside:
            m = MODULE_ROW.match(line)
            if m:
                rows.add(m.group(1))
    return rows


def compare(kind, present, listed, where, problems):
    for name in sorted(present - listed):
        problems.append(f"{kind} {name} is missing from {where}")
    for name in sorted(listed - present):
        problems.append(f"{where} lists {kind.split('/')[0]}/{name}, which does not exist")


def check_docs(root, problems):
    library = read_lines(os.path.join(root, "docs", "library.md"), problems)
    tools = read_lines(os.path.join(root, "docs", "tools.md"), problems)
    modules = folders_with(root, "lib", "CMakeLists.txt")
    programs = folders_with(root, "apps", "main.cpp", skip={"common"})
    compare("lib/ module", modules, module_rows(library), "docs/library.md's module table", problems)
    sections = {m.group(1) for m in map(PROGRAM_HEADING.match, tools) if m}
    compare("apps/ program", programs, sections, "docs/tools.md's '## <program>' sections", problems)


def sources(root):
    """The tree's C/C++ sources: git's tracked and untracked-but-not-ignored files, or every file outside a
    build folder when root is not the top of a git work tree (the fixture's tree lies inside the build folder)."""
    try:
        top = subprocess.run(["git", "-C", root, "rev-parse", "--show-toplevel"], capture_output=True, text=True,
                             check=True).stdout.strip()
        if os.path.realpath(top) != os.path.realpath(root):
            raise ValueError(top)
        out = subprocess.run(["git", "-C", root, "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
                             capture_output=True, check=True).stdout.decode()
        names = [n for n in out.split("\0") if n]
    except (OSError, ValueError, subprocess.CalledProcessError):
        names = []
        for d, subdirs, files in os.walk(root):
            subdirs[:] = [s for s in subdirs if not s.startswith(("build", "."))]
            names += [os.path.relpath(os.path.join(d, f), root) for f in files]
    return sorted(n for n in set(names)
                  if n.endswith(SOURCE_SUFFIXES) and os.path.isfile(os.path.join(root, n)))


def check_format(root, clang_format, problems):
    files = sources(root)
    bad = set()
    for i in range(0, len(files), 100):
        batch = files[i:i + 100]
        run = subprocess.run([clang_format, "--dry-run", "-Werror", *batch], cwd=root, capture_output=True,
                             text=True)
        if run.returncode != 0:
            # clang-format -Werror: "path:line:col: error: code should be clang-formatted [-Wclang-format-violations]"
            found = {line.split(":", 1)[0] for line in run.stderr.splitlines() if ": error: " in line}
            bad |= found & set(batch) or {f"(clang-format exit {run.returncode}: {run.stderr.strip()[:200]})"}
    for name in sorted(bad):
        problems.append(f"{name} is not formatted by .clang-format (run: clang-format -i {name})")
    return len(files)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="the source tree")
    parser.add_argument("--clang-format", default=shutil.which("clang-format") or "",
                        help="clang-format to run (empty: skip the format check)")
    args = parser.parse_args()
    if not os.path.isdir(os.path.join(args.root, "lib")):
        parser.error(f"--root {args.root}: no lib/ folder there")
    problems = []
    check_docs(args.root, problems)
    if args.clang_format and os.access(args.clang_format, os.X_OK):
        count = check_format(args.root, args.clang_format, problems)
        print(f"format: {count} C/C++ sources checked with {args.clang_format}")
    else:
        print("format: SKIPPED, clang-format not found (scripts/setup installs Debian's clang-format)")
    for p in problems:
        print(p, file=sys.stderr)
    print(f"docs_and_format: {'FAILED, ' + str(len(problems)) + ' finding(s)' if problems else 'ok'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
