#!/usr/bin/env python3
"""gen-configs --scene end to end on the example scenes (scripts/make-scene; SPEC 7).

A case is DECK:PAIR:SURFACE (e.g. hertz:0:gregory) or "errors". For a scene it runs both global searches,
the paper's (--search nearest_node, SPEC 7) and the surface search (the default, SPEC 9), and checks:
  - exit 0 and the summary's counts;
  - the columns exactly as SPEC 7 lists them, one row per slave node, the slave ids those of the deck's
    manifest (DECK.json, written by make-scene from what it put in the deck), in increasing order;
  - no_segment rows: status no_segment and every other field after `slave` empty; other rows: node ids,
    finite coordinates, unit node normals (Gregory), a SPEC 2 status;
  - the file is a RAW.csv for `gen-configs --input`, which reproduces every label column character for
    character, and for `evaluate-net --input` with a shipped network (one prediction per row);
  - surface search: SPEC 9's columns after SPEC 7's; every found row has status ok, a location, a face type
    with its number of distinct nodes; a quad4 row the closest point P with |gap| = |S - P|, P on the bilinear
    facet at the row's (xi, eta) in the a,b,c,d order, a face whose nodes are a,b,c,d in its own cycle, and a
    `face` row's (xi, eta) are label mode's (the stationary point); any other face's row has the SPEC 7 columns
    empty and its own local coordinates inside its domain.
"errors" checks a malformed deck (exit 3, file and line named), a pair that does not exist (exit 2), a missing
include (exit 4, the file named), and that no output is left behind by any of them.

Usage: scene_app.py --gen-configs PATH --evaluate-net PATH --scenes DIR --weights DIR --work DIR --case CASE
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys

POINTS = ["ax", "ay", "az", "bx", "by", "bz", "cx", "cy", "cz", "dx", "dy", "dz", "sx", "sy", "sz"]
NORMALS = ["nax", "nay", "naz", "nbx", "nby", "nbz", "ncx", "ncy", "ncz", "ndx", "ndy", "ndz"]
STATUSES = {"ok", "outside", "no_convergence", "degenerate", "invalid"}
# Unit normals written with round-trip precision: |n| = 1 up to a few roundings.
UNIT_TOL = 1e-12
# SPEC 9's face types and their node counts (the `nodes` column: corners, then mid-side nodes).
FACE_NODES = {"quad4": 4, "quad8": 8, "tri3": 3, "tri6": 6}


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def run(args, expect):
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != expect:
        raise Failure("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" %
                      (" ".join(args), result.returncode, expect, result.stdout, result.stderr))
    return result


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def bilinear_point(r, column, xi, eta):
    """P(xi, eta) of the row's bilinear facet A, B, C, D (SPEC 1)."""
    shape = [(1 - xi) * (1 - eta) / 4, (1 + xi) * (1 - eta) / 4, (1 + xi) * (1 + eta) / 4, (1 - xi) * (1 + eta) / 4]
    return [sum(shape[i] * float(r[column[n + c]]) for i, n in enumerate("abcd")) for c in "xyz"]


def surface_case(opts, deck, pair, surface, work):
    """The surface search's rows (SPEC 9)."""
    out = os.path.join(work, "surface-pairs.csv")
    run([opts.gen_configs, "--scene", os.path.join(opts.scenes, deck + ".inp"), "--pair", str(pair),
         "--surface", surface, "--output", out], 0)
    header, rows = read_csv(out)
    names = ["xi", "eta"] if surface == "bilinear" else ["u", "v"]
    expected_header = (["slave", "a", "b", "c", "d"] + POINTS + (NORMALS if surface == "gregory" else []) +
                       names + ["status", "gap", "iterations", "location", "px", "py", "pz", "face_type", "nodes"])
    check(header == expected_header, "surface search header %s, expected %s" % (header, expected_header))
    column = {name: i for i, name in enumerate(header)}
    face_rows = []
    locations = {"face": 0, "edge": 0, "vertex": 0}
    for r in rows:
        if r[column["status"]] == "no_segment":
            continue
        check(r[column["status"]] == "ok", "surface search status %r" % r[column["status"]])
        location = r[column["location"]]
        check(location in locations, "location %r" % location)
        locations[location] += 1
        face_type = r[column["face_type"]]
        check(face_type in FACE_NODES, "face_type %r" % face_type)
        nodes = r[column["nodes"]].split(" ")
        check(len(nodes) == FACE_NODES[face_type] and len(set(nodes)) == len(nodes),
              "slave %s: %s face with nodes %s" % (r[0], face_type, nodes))
        if face_type != "quad4":
            # SPEC 9: no SPEC 7 configuration for other faces; their own local coordinates ((r, s) of a triangle,
            # (xi, eta) of a quad8, under either --surface) in the coordinate columns.
            spec7 = ["a", "b", "c", "d"] + POINTS + (NORMALS if surface == "gregory" else [])
            check(all(r[column[n]] == "" for n in spec7), "slave %s: %s row %s" % (r[0], face_type, r))
            a, b = float(r[column[names[0]]]), float(r[column[names[1]]])
            inside = (a >= 0 and b >= 0 and a + b <= 1 + 1e-12) if face_type.startswith("tri") else \
                (abs(a) <= 1 + 1e-12 and abs(b) <= 1 + 1e-12)
            check(inside, "slave %s: %s coordinates (%r, %r)" % (r[0], face_type, a, b))
            continue
        s = [float(r[column["s" + c]]) for c in "xyz"]
        p = [float(r[column["p" + c]]) for c in "xyz"]
        scale = max(1.0, max(abs(x) for x in s))
        distance = math.dist(s, p)
        check(abs(abs(float(r[column["gap"]])) - distance) <= 1e-12 * scale,
              "slave %s: gap %s, |S - P| %r" % (r[0], r[column["gap"]], distance))
        abcd = [r[column[n]] for n in "abcd"]
        k = nodes.index(abcd[0]) if abcd[0] in nodes else -1
        check(k >= 0 and [nodes[(k + i) % 4] for i in range(4)] == abcd,
              "slave %s: nodes %s are not a,b,c,d %s in the face's cycle" % (r[0], nodes, abcd))
        if surface == "bilinear":
            q = bilinear_point(r, column, float(r[column["xi"]]), float(r[column["eta"]]))
            check(math.dist(p, q) <= 1e-12 * scale, "slave %s: P %s is not the facet's point %s" % (r[0], p, q))
        if location == "face":
            face_rows.append(r)
    # A face point is the stationary point of SPEC 2: label mode finds it too.
    relabelled = os.path.join(work, "surface-relabelled.csv")
    run([opts.gen_configs, "--surface", surface, "--input", out, "--output", relabelled], 0)
    header2, rows2 = read_csv(relabelled)
    column2 = {name: i for i, name in enumerate(header2)}
    by_slave = {r2[column2["slave"]]: r2 for r2 in rows2}
    for r in face_rows:
        r2 = by_slave[r[0]]
        check(r2[column2["status"]] == "ok", "slave %s: label mode status %r for a face point" %
              (r[0], r2[column2["status"]]))
        for name in names:
            check(abs(float(r[column[name]]) - float(r2[column2[name]])) <= 1e-9,
                  "slave %s: %s %s by the surface search, %s by label mode" %
                  (r[0], name, r[column[name]], r2[column2[name]]))
    return locations


def scene_case(opts, deck, pair, surface):
    work = os.path.join(opts.work, "%s-%d-%s" % (deck, pair, surface))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    manifest = json.load(open(os.path.join(opts.scenes, deck + ".json")))
    expected = manifest["pairs"][pair]
    out = os.path.join(work, "pairs.csv")
    result = run([opts.gen_configs, "--scene", os.path.join(opts.scenes, deck + ".inp"), "--pair", str(pair),
                  "--surface", surface, "--search", "nearest_node", "--output", out], 0)

    # Columns exactly as SPEC 7 lists them.
    header, rows = read_csv(out)
    names = ["xi", "eta"] if surface == "bilinear" else ["u", "v"]
    expected_header = (["slave", "a", "b", "c", "d"] + POINTS + (NORMALS if surface == "gregory" else []) +
                       names + ["status", "gap", "iterations"])
    check(header == expected_header, "header %s, expected %s" % (header, expected_header))
    column = {name: i for i, name in enumerate(header)}

    # One row per slave node of the manifest, in increasing id.
    slaves = [int(r[0]) for r in rows]
    check(slaves == sorted(expected["slave_nodes"]),
          "slave column %s..., expected the manifest's %d nodes %s..." %
          (slaves[:8], len(expected["slave_nodes"]), sorted(expected["slave_nodes"])[:8]))

    no_segment = 0
    for r in rows:
        check(len(r) == len(header), "ragged row %s" % r)
        status = r[column["status"]]
        if status == "no_segment":
            no_segment += 1
            check(all(r[i] == "" for i in range(1, len(r)) if i != column["status"]),
                  "no_segment row with values: %s" % r)
            continue
        check(status in STATUSES, "status %r" % status)
        for name in ["a", "b", "c", "d", "iterations"]:
            check(re.fullmatch(r"[0-9]+", r[column[name]]) is not None, "%s = %r" % (name, r[column[name]]))
        check(len({r[column[n]] for n in "abcd"}) == 4, "repeated node in %s" % r[:5])
        for name in POINTS + (NORMALS if surface == "gregory" else []):
            check(math.isfinite(float(r[column[name]])), "%s = %r" % (name, r[column[name]]))
        if surface == "gregory":
            for node in "abcd":
                n = [float(r[column["n%s%s" % (node, c)]]) for c in "xyz"]
                check(abs(math.sqrt(sum(x * x for x in n)) - 1.0) < UNIT_TOL, "normal at %s not unit: %s" % (node, n))
        has_value = status in ("ok", "outside")
        for name in names + ["gap"]:
            check((r[column[name]] != "") == has_value, "%s = %r with status %s" % (name, r[column[name]], status))

    # The summary agrees with the file.
    summary = result.stdout
    found = re.search(r"pairs found +(\d+)", summary)
    missing = re.search(r"no_segment +(\d+)", summary)
    slave_line = re.search(r"slave nodes +(\d+)", summary)
    check(found and missing and slave_line, "summary lacks counts:\n" + summary)
    check(int(slave_line.group(1)) == len(rows), "summary says %s slave nodes, file has %d rows" %
          (slave_line.group(1), len(rows)))
    check(int(missing.group(1)) == no_segment, "summary says %s no_segment, file has %d" % (missing.group(1), no_segment))
    check(int(found.group(1)) == len(rows) - no_segment, "summary's pairs found")
    for label in ["interior angle", "aspect ratio", "warp", "normal offset"] + (
            ["node-normal tilt"] if surface == "gregory" else []):
        check(re.search(label + r"[^\n]*[0-9.e+-]+ / [0-9.e+-]+ / [0-9.e+-]+", summary) or no_segment == len(rows),
              "summary lacks the %s statistics:\n%s" % (label, summary))
    skipped = expected["skipped_master_faces"]
    for kind, count in skipped.items():
        check(re.search(r"faces skipped +master: [^\n]*%s %d" % (kind, count), summary),
              "summary does not say %s %d skipped:\n%s" % (kind, count, summary))
    segments = re.search(r"master segments +(\d+)", summary)
    check(segments and int(segments.group(1)) == expected["master_segments"],
          "summary's master segments, expected %d:\n%s" % (expected["master_segments"], summary))

    # The file itself is a RAW.csv (SPEC 7) for label mode, which reproduces every label (no_segment rows:
    # status no_segment, the rest empty), and for evaluate-net, which predicts one row per row.
    raw = out
    kept = rows
    relabelled = os.path.join(work, "relabelled.csv")
    run([opts.gen_configs, "--surface", surface, "--input", raw, "--output", relabelled], 0)
    header2, rows2 = read_csv(relabelled)
    check(len(rows2) == len(kept), "label mode wrote %d rows for %d" % (len(rows2), len(kept)))
    column2 = {name: i for i, name in enumerate(header2)}
    for r, r2 in zip(kept, rows2):
        for name in names + ["status", "gap", "iterations"]:
            check(r[column[name]] == r2[column2[name]], "slave %s: %s %r in scene mode, %r in label mode" %
                  (r[0], name, r[column[name]], r2[column2[name]]))
        check(r2[column2["slave"]] == r[0], "label mode lost the slave column")
    weights = os.path.join(opts.weights, "bilinear-8.h5" if surface == "bilinear" else "gregory-48.h5")
    predicted = os.path.join(work, "predicted.csv")
    run([opts.evaluate_net, "--weights", weights, "--input", raw, "--output", predicted], 0)
    header3, rows3 = read_csv(predicted)
    check(len(rows3) == len(kept) and "slave" in header3 and names[0] in header3,
          "evaluate-net wrote %d rows, header %s" % (len(rows3), header3))
    column3 = {name: i for i, name in enumerate(header3)}
    for r, r3 in zip(kept, rows3):
        missing_pair = r[column["status"]] == "no_segment"
        check((r3[column3["status"]] == "no_segment") == missing_pair, "slave %s: evaluate-net status %r for %r" %
              (r[0], r3[column3["status"]], r[column["status"]]))
        check((r3[column3[names[0]]] == "") == missing_pair, "slave %s: prediction %r" % (r[0], r3[column3[names[0]]]))
    locations = surface_case(opts, deck, pair, surface, work)
    print("%s pair %d %s: %d rows, %d no_segment, labels reproduced, evaluate-net read it; surface search: %s" %
          (deck, pair, surface, len(rows), no_segment, locations))


def errors_case(opts):
    work = os.path.join(opts.work, "errors")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "never.csv")
    bad = os.path.join(work, "bad.inp")
    with open(bad, "w") as f:
        f.write("*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 5, 6, 7, 8\n")
    r = run([opts.gen_configs, "--scene", bad, "--output", out], 3)
    check(re.search(r"error: '[^']*bad.inp':4: \*ELEMENT: element 1: node 2 \(node 2 of the element\) is not defined",
                    r.stderr), "message: " + r.stderr)
    r = run([opts.gen_configs, "--scene", os.path.join(opts.scenes, "flat.inp"), "--pair", "2", "--output", out], 2)
    check("the deck has 2" in r.stderr, "message: " + r.stderr)
    missing = os.path.join(work, "missing.inp")
    with open(missing, "w") as f:
        f.write("** a deck whose include is not there\n*INCLUDE, INPUT=sub/nodes.inp\n")
    r = run([opts.gen_configs, "--scene", missing, "--output", out], 4)
    check(re.search(r"missing.inp':2: \*INCLUDE: cannot open INPUT='sub/nodes.inp'", r.stderr), "message: " + r.stderr)
    check(sorted(os.listdir(work)) == ["bad.inp", "missing.inp"], "left behind: %s" % os.listdir(work))
    print("errors: exit 3 / 2 / 4 with file and line, nothing left behind")


def main():
    parser = argparse.ArgumentParser()
    for name in ["--gen-configs", "--evaluate-net", "--scenes", "--weights", "--work", "--case"]:
        parser.add_argument(name, required=True)
    opts = parser.parse_args()
    try:
        if opts.case == "errors":
            errors_case(opts)
        else:
            deck, pair, surface = opts.case.split(":")
            scene_case(opts, deck, int(pair), surface)
    except Failure as e:
        print("FAIL %s: %s" % (opts.case, e))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
