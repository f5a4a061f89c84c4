#!/usr/bin/env python3
"""The examples of the contact search handle (examples/), built against the INSTALLED package and checked against
gen-configs --scene on the same geometry.

1. Configures and builds examples/ in a fresh directory against PREFIX alone (CMAKE_PREFIX_PATH=PREFIX), as an FE
   code's build would find contactnn.
2. Runs contact_search_c DIR (which also writes each increment's mesh as DIR/incNN.inp) and contact_search_fortran.
3. Runs gen-configs --scene DIR/incNN.inp for every increment and compares, for each program and increment: the
   same slave nodes found (status ok), each on the same face (the deck's element whose top face has the same node
   set), at the same location (face, edge, vertex); the point and the gap within 1e-10 of the face size; the normal
   a unit vector with gap = (S - P).n.
4. With --valgrind: both programs again under valgrind's memcheck (no error, no definite leak, the same output).

Exit 0 passed, 1 failed. The expected answers come from gen-configs, an independent program of the project (the
deck reader, lib/mesh's surface, the surface search), never from the examples' own output.

Usage: check_examples.py --cmake CMAKE --generator G --prefix PREFIX --source-dir SRC --gen-configs P --work DIR
                         [--valgrind VALGRIND] [--set VAR=VALUE]...
"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failures, add_consumer_options, build_consumer, run_or_exit  # noqa: E402  (tests/check_support.py)

TOL = 1e-10  # of the face size (the plate's cells are 1 x 1)
failures = Failures()
fail = failures.fail
run = run_or_exit


def read_deck(path):
    """Node coordinates by id, and each element's top face (the last 4 nodes of a C3D8, the last 3 of a C3D6)."""
    nodes, faces = {}, {}
    section = None
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                keyword = line.upper()
                section = ("node" if keyword.startswith("*NODE,") or keyword == "*NODE" else
                           "C3D8" if "TYPE=C3D8" in keyword else "C3D6" if "TYPE=C3D6" in keyword else None)
                continue
            fields = [v.strip() for v in line.split(",") if v.strip()]
            if section == "node":
                nodes[int(fields[0])] = tuple(float(v) for v in fields[1:4])
            elif section in ("C3D8", "C3D6"):
                ids = [int(v) for v in fields]
                faces[ids[0]] = frozenset(ids[-4:] if section == "C3D8" else ids[-3:])
    return nodes, faces


def read_program_output(text):
    """{increment: {node: (face, face_type, location, gap, point, normal)}}."""
    out = {}
    for line in text.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        v = line.split()
        k, node, face = int(v[0]), int(v[1]), int(v[2])
        numbers = [float(x) for x in v[5:12]]
        out.setdefault(k, {})[node] = (face, v[3], v[4], numbers[0], numbers[1:4], numbers[4:7])
    return out


def read_scene_csv(path):
    """{node: (location, gap, point, face node set)} of the rows with status ok."""
    rows = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["status"] != "ok":
                continue
            rows[int(row["slave"])] = (row["location"], float(row["gap"]),
                                       [float(row["px"]), float(row["py"]), float(row["pz"])],
                                       frozenset(int(n) for n in row["nodes"].split()))
    return rows


def compare(name, answers, k, expected, nodes, faces):
    found = answers.get(k, {})
    if set(found) != set(expected):
        fail(f"{name}, increment {k}: slave nodes found {sorted(set(found) ^ set(expected))} differ from gen-configs'")
    for node in sorted(set(found) & set(expected)):
        face, face_type, location, gap, point, normal = found[node]
        e_location, e_gap, e_point, e_nodes = expected[node]
        where = f"{name}, increment {k}, slave node {node}"
        if faces.get(face) != e_nodes:
            fail(f"{where}: face {face} {sorted(faces.get(face, []))}, gen-configs' face {sorted(e_nodes)}")
        if (face_type == "quad4") != (len(e_nodes) == 4):
            fail(f"{where}: face type {face_type} for a face of {len(e_nodes)} nodes")
        if location != e_location:
            fail(f"{where}: location {location}, gen-configs' {e_location}")
        if abs(gap - e_gap) > TOL or max(abs(a - b) for a, b in zip(point, e_point)) > TOL:
            fail(f"{where}: gap {gap!r} point {point}, gen-configs' {e_gap!r} {e_point}")
        s = nodes[node]
        length = math.sqrt(sum(c * c for c in normal))
        along = sum((s[i] - point[i]) * normal[i] for i in range(3))
        if abs(length - 1.0) > 1e-12 or abs(along - gap) > 1e-9:
            fail(f"{where}: normal {normal} (length {length}), (S - P).n = {along} for gap {gap}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_consumer_options(parser)
    parser.add_argument("--gen-configs", required=True)
    args = parser.parse_args()

    build, _ = build_consumer(args, os.path.join(args.source_dir, "examples"))
    decks = os.path.join(args.work, "decks")
    os.makedirs(decks)
    programs = {"C": [os.path.join(build, "contact_search_c"), decks],
                "Fortran": [os.path.join(build, "contact_search_fortran")]}
    outputs = {name: run(command).stdout for name, command in programs.items()}
    answers = {name: read_program_output(text) for name, text in outputs.items()}

    increments = sorted({k for a in answers.values() for k in a})
    if increments != list(range(11)):
        fail(f"increments printed {increments}, expected 0 to 10")
    contacts = 0
    for k in range(11):
        deck = os.path.join(decks, f"inc{k:02d}.inp")
        table = os.path.join(decks, f"inc{k:02d}.csv")
        run([args.gen_configs, "--scene", deck, "--pair", "0", "--output", table])
        nodes, faces = read_deck(deck)
        expected = read_scene_csv(table)
        contacts += len(expected)
        for name in programs:
            compare(name, answers[name], k, expected, nodes, faces)
    print(f"{contacts} slave node answers of gen-configs over 11 increments, compared with the C and Fortran examples")

    if args.valgrind and shutil.which(args.valgrind):
        memcheck = [args.valgrind, "--tool=memcheck", "--error-exitcode=99", "--leak-check=full",
                    "--errors-for-leak-kinds=definite", "--show-leak-kinds=definite", "-q"]
        for name, command in programs.items():
            if name == "C":
                command = [command[0], os.path.join(args.work, "decks-valgrind")]
                os.makedirs(command[1])
            p = subprocess.run(memcheck + command, capture_output=True, text=True)
            if p.returncode != 0:
                fail(f"{name} example under valgrind: exit {p.returncode}\n{p.stderr[-4000:]}")
            elif p.stdout != outputs[name]:
                fail(f"{name} example under valgrind: another output than outside it")
        print("valgrind memcheck: both examples clean")
    elif args.valgrind:
        print(f"valgrind ({args.valgrind}) not found: the memcheck runs are skipped")

    return failures.exit_status("PASS: the examples answer as gen-configs --scene",
                                f"FAIL: {len(failures)} differences")


if __name__ == "__main__":
    sys.exit(main())
