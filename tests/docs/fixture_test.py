#!/usr/bin/env python3
"""check_docs_and_format.py on a tree of its own: a tiny lib/, apps/ and docs/ that pass, then each way they can
fail (a module or program added without its docs row, a row for one that does not exist, a badly formatted
source), each of which must make the check fail and name what is wrong.

  fixture_test.py --work DIR [--clang-format PATH]
"""
import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CHECK = os.path.join(HERE, "check_docs_and_format.py")
REPO_CLANG_FORMAT = os.path.join(HERE, "..", "..", ".clang-format")

LIBRARY_MD = """# The library

## Modules and their dependencies

| module | what it holds | links |
|---|---|---|
| `core` | errors | Eigen |
| `search` | the search | core |

## API reference
| `notamodule` | a table elsewhere is not the module table | |
"""
TOOLS_MD = """# The tools

## What every tool does alike

## find-it

Finds it.

## The scripts
"""
GHOST_ROW = "| `ghost` | gone | core |\n"
GOOD_CPP = "int add(int a, int b) { return a + b; }\n"
BAD_CPP = "int  add( int a,int b ){return a+b;}\n"


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def make_tree(root):
    shutil.rmtree(root, ignore_errors=True)
    write(root, "lib/core/CMakeLists.txt", "")
    write(root, "lib/core/add.cpp", GOOD_CPP)
    write(root, "lib/search/CMakeLists.txt", "")
    write(root, "apps/find-it/main.cpp", "int main() { return 0; }\n")
    write(root, "apps/common/cli.cpp", GOOD_CPP)  # apps/common is no program
    write(root, "docs/library.md", LIBRARY_MD)
    write(root, "docs/tools.md", TOOLS_MD)
    shutil.copyfile(REPO_CLANG_FORMAT, os.path.join(root, ".clang-format"))


def run_check(root, clang_format):
    run = subprocess.run([sys.executable, CHECK, "--root", root, "--clang-format", clang_format],
                         capture_output=True, text=True)
    return run.returncode, run.stdout + run.stderr


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--work", required=True)
    parser.add_argument("--clang-format", default=shutil.which("clang-format") or "")
    args = parser.parse_args()
    formatter = args.clang_format if args.clang_format and os.access(args.clang_format, os.X_OK) else ""
    root = os.path.join(args.work, "tree")

    def append(rel, text):
        with open(os.path.join(root, rel), "a", encoding="utf-8") as f:
            f.write(text)

    # (name, change to the passing tree, the text the failure must print; None: the check must pass)
    cases = [
        ("the tree as made passes", lambda: None, None),
        ("a module added without a docs row", lambda: write(root, "lib/newmod/CMakeLists.txt", ""),
         "lib/ module newmod is missing from docs/library.md"),
        ("a docs row for a module lib/ lacks",  # the row inside the module table
         lambda: write(root, "docs/library.md", LIBRARY_MD.replace("| `search` |", GHOST_ROW + "| `search` |")),
         "lists lib/ghost, which does not exist"),
        ("a program added without a tools.md section", lambda: write(root, "apps/new-tool/main.cpp", GOOD_CPP),
         "apps/ program new-tool is missing from docs/tools.md"),
        ("a tools.md section for a program apps/ lacks", lambda: append("docs/tools.md", "\n## gone-tool\n"),
         "lists apps/gone-tool, which does not exist"),
        ("without clang-format a badly formatted file is not judged",
         lambda: write(root, "lib/core/bad.cpp", BAD_CPP), "format: SKIPPED"),
    ]
    if formatter:
        cases.append(("a badly formatted source", lambda: write(root, "lib/core/bad.cpp", BAD_CPP),
                      "lib/core/bad.cpp is not formatted"))
    else:
        print("fixture: the badly formatted case SKIPPED, clang-format not found")

    failures = 0
    for name, change, expected in cases:
        make_tree(root)
        change()
        skip_format = expected == "format: SKIPPED"
        code, output = run_check(root, "" if skip_format else formatter)
        if expected is None:
            ok = code == 0
        elif skip_format:
            ok = code == 0 and expected in output
        else:
            ok = code == 1 and expected in output
        print(f"{'ok  ' if ok else 'FAIL'} {name}: exit {code}")
        if not ok:
            failures += 1
            print(f"     expected {'exit 0' if expected is None or skip_format else 'exit 1'}"
                  f"{'' if expected is None else ' and ' + repr(expected)}; output:\n{output}")
    shutil.rmtree(root, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
