#!/usr/bin/env python3
"""CalculiX histories (scripts/make-scene hertz-slide, forming-stroke, and the quadratic tet-press and tubes-press)
against contactnn (SPEC 10), and the pieces of scripts/calculix-compare that need no solver.

Cases:
  frd-reader        calculix-compare's .frd reader on small hand-written files: the long and the short format,
                    values that touch, continuation records, COPEN paired with its increment's DISP, and
                    malformed files (exit 3 naming file and line); the half-ulp of a printed value; the scratch
                    copy of --lengthen-static (*STATIC data line replaced, output added, includes absolute).
  make-scene-options  every option of make-scene checked before any work: nan, inf, out of range, an option
                    no chosen kind uses: exit 2, a message naming the option, nothing written.
  reference:KIND    the history KIND run by ccx, compared by calculix-compare with the Python reference
                    search (surface_search_reference.py) in place of gen-configs: passes; the history has
                    contacts in every increment and slave nodes that move to another master face across an
                    edge; a reference that drops a contact or moves every gap by 1e-3 fails (exit 1); without
                    the `nodes` column the bound is taken over all nodes and it still passes.
                    For the quadratic histories (tet-press: a C3D10 master, tri6 faces; tubes-press: C3D20 on
                    C3D20, quad8 faces and mid-side slave nodes) the plain comparison only: the perturbed ones test
                    calculix-compare itself, which the linear histories do.
  gen-configs:KIND  the history KIND run by ccx, compared by calculix-compare with contactnn's gen-configs
                    (--gen-configs PATH): every contact found, |gap - COPEN| within the .frd's precision; for the
                    quadratic histories also every contact's face of the expected type (tri6, quad8) and, for
                    tubes-press, contacts at mid-side slave nodes.
The cases that run ccx exit 77 (ctest: skipped) with a message when ccx is not installed.

Usage: calculix_histories.py --case CASE --work DIR [--gen-configs PATH]
"""
import argparse
import importlib.machinery
import importlib.util
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
MAKE_SCENE = os.path.join(ROOT, "scripts", "make-scene")
COMPARE = os.path.join(ROOT, "scripts", "calculix-compare")
REFERENCE = os.path.join(HERE, "surface_search_reference.py")
SKIP = 77
# What each history must show with its defaults (scripts/make-scene): contacts in every increment, and at
# least this many moves of a slave node to a face sharing an edge with its previous one.
EDGE_CROSSINGS = {"hertz-slide": 5, "forming-stroke": 1, "tet-press": 5, "tubes-press": 5}
# The quadratic histories: the face type of every contact's point, and whether mid-side slave nodes must be in
# contact (the manifest's corner_slave_nodes are the others).
QUADRATIC = {"tet-press": ("tri6", False), "tubes-press": ("quad8", True)}


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def run(command, expect, cwd=None):
    result = subprocess.run(command, capture_output=True, text=True, cwd=cwd)
    if expect is not None and result.returncode != expect:
        raise Failure("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" %
                      (" ".join(command), result.returncode, expect, result.stdout, result.stderr))
    return result


def load_compare():
    loader = importlib.machinery.SourceFileLoader("calculix_compare", COMPARE)
    spec = importlib.util.spec_from_loader("calculix_compare", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


# The lines that open a block of displacements (D1, D2, D3, ALL) and one of contact results (COPEN ... CSHEAR2),
# as ccx writes them.
DISP_HEADER = """ -4  DISP        4    1
 -5  D1          1    2    1    0
 -5  D2          1    2    2    0
 -5  D3          1    2    3    0
 -5  ALL         1    2    0    0    1ALL
"""
CONTACT_HEADER = """ -4  CONTACT     6    1
 -5  COPEN       1    4    1    1
 -5  CSLIP1      1    4    2    2
 -5  CSLIP2      1    4    3    3
 -5  CPRESS      1    4    1    2
 -5  CSHEAR1     1    4    2    3
 -5  CSHEAR2     1    4    3    1
"""


# ---------------------------------------------------------------------------------------------------------
# frd-reader
def frd_reader_case(work):
    cc = load_compare()
    # Long format (ids in 10 columns), values touching, a continuation record, and a COPEN block of the
    # same step number after each DISP block; an increment without COPEN.
    long_frd = f"""    1C
    2C                             3                                     1
 -1         1 1.00000E+00-2.00000E+00 0.00000E+00
 -1         2 1.23456E+01 3.00000E-01-4.50000E+02
 -1        10-1.00000E-03 0.00000E+00 1.00000E+00
 -3
    1PSTEP                         1           1           1
  100CL  101 5.00000E-01           3                     0    1           1
{DISP_HEADER} -1         1 1.00000E-02-2.00000E-02 3.00000E-02
 -1         2 0.00000E+00 0.00000E+00 0.00000E+00
 -1        10 0.00000E+00 0.00000E+00-5.00000E-03
 -3
    1PSTEP                         2           1           1
  100CL  101 5.00000E-01           2                     0    1           1
{CONTACT_HEADER} -1         1-1.25000E-03 1.00000E-06 2.00000E-06 3.00000E+01 0.00000E+00
 -2           0.00000E+00
 -1        10 2.00000E-03 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00
 -3
    1PSTEP                         3           2           1
  100CL  102 1.00000E+00           3                     0    2           1
{DISP_HEADER} -1         1 2.00000E-02-4.00000E-02 6.00000E-02
 -1         2 0.00000E+00 0.00000E+00 0.00000E+00
 -1        10 0.00000E+00 0.00000E+00-1.00000E-02
 -3
 9999
"""
    path = os.path.join(work, "long.frd")
    open(path, "w").write(long_frd)
    frd = cc.Frd(path)
    check(sorted(frd.nodes) == [1, 2, 10], "nodes %s, expected [1, 2, 10]" % sorted(frd.nodes))
    check(frd.nodes[2][0] == (12.3456, 0.3, -450.0), "node 2 at %s" % (frd.nodes[2][0],))
    check(frd.nodes[10][0] == (-1e-3, 0.0, 1.0), "node 10 (touching values) at %s" % (frd.nodes[10][0],))
    check(frd.nodes[2][1] == (0.5e-4, 0.5e-6, 0.5e-3), "node 2's half-ulps %s" % (frd.nodes[2][1],))
    check(len(frd.increments) == 2, "%d increments, expected 2" % len(frd.increments))
    first, second = frd.increments
    check((first["step"], first["inc"], second["inc"]) == (1, 1, 2), "steps and increments %s" % frd.increments)
    check(first["disp"][10][0] == (0.0, 0.0, -5e-3), "increment 1, node 10's DISP %s" % (first["disp"][10][0],))
    check(first["contact"] == {1: (-1.25e-3, 0.5e-8), 10: (2e-3, 0.5e-8)},
          "increment 1's COPEN %s" % first["contact"])
    check(second["contact"] is None, "increment 2 has no COPEN block, got %s" % second["contact"])
    check(abs(frd.node_error(2, first) - ((0.5e-4 + 0.5e-5) ** 2 + (0.5e-6 + 0.5e-5) ** 2 +
                                          (0.5e-3 + 0.5e-5) ** 2) ** 0.5) < 1e-18, "node_error of node 2")
    check(cc.half_ulp("-7.33472E-03") == 0.5e-8 and cc.half_ulp(" 1.0E+02") == 5.0, "half_ulp")

    # Short format (ids in 5 columns).
    short_frd = """    2C                             2                                     0
 -1    1 1.00000E+00 2.00000E+00 3.00000E+00
 -1  123-1.00000E+00-2.00000E+00-3.00000E+00
 -3
  100CL  101 1.00000E+00           2                     0    1           0
 -4  DISP        4    1
 -5  D1          1    2    1    0
 -1    1 1.00000E-01 0.00000E+00 0.00000E+00
 -1  123 0.00000E+00 0.00000E+00 2.00000E-01
 -3
 9999
"""
    path = os.path.join(work, "short.frd")
    open(path, "w").write(short_frd)
    frd = cc.Frd(path)
    check(frd.nodes[123][0] == (-1.0, -2.0, -3.0) and frd.increments[0]["disp"][123][0] == (0.0, 0.0, 0.2),
          "short format: node 123 %s, DISP %s" % (frd.nodes[123][0], frd.increments[0]["disp"][123][0]))

    # Malformed files: exit 3 from the reader, naming the file and the line.
    lines = long_frd.splitlines(keepends=True)
    broken = {
        "number": (lines[:3] + [" -1         2 1.2345XE+01 3.00000E-01-4.50000E+02\n"] + lines[4:], 4),
        "no-end": (lines[:14], 14),
        "binary": ([lines[0], lines[1].rstrip("\n")[:-1] + "2\n"] + lines[2:], 2),
        "contact-first": (lines[:6] + lines[18:], 18),
        "no-disp": (lines[:6] + [" 9999\n"], 7),
    }
    for name, (content, line) in broken.items():
        path = os.path.join(work, "broken-%s.frd" % name)
        open(path, "w").write("".join(content))
        try:
            cc.Frd(path)
            raise Failure("%s: read without an error" % path)
        except cc.Failure as e:
            check(e.status == 3, "%s: status %d, expected 3" % (path, e.status))
            check(str(e).startswith("%s:%d:" % (path, line)), "%s: message '%s' does not name line %d" %
                  (path, e, line))

    # The scratch copy of --lengthen-static.
    os.makedirs(os.path.join(work, "deck", "inc"), exist_ok=True)
    deck = os.path.join(work, "deck", "job.inp")
    open(deck, "w").write("*INCLUDE, INPUT=inc/nodes.inp\n*STEP\n*STATIC\n** a comment\n0.001,0.001,1e-7,0.01\n"
                          "*BOUNDARY\nN1,1,3\n*END STEP\n*Step\n*static\n*end step\n")
    copy = cc.prepared_deck(deck, "0.01,1.0,1e-7,0.02")
    expected = ["*INCLUDE, INPUT=%s" % os.path.join(os.path.dirname(os.path.abspath(deck)), "inc/nodes.inp"), "*STEP", "*STATIC",
                "** a comment", "0.01,1.0,1e-7,0.02", "*BOUNDARY", "N1,1,3", "*NODE FILE", "U", "*CONTACT FILE",
                "CDIS, CSTR", "*END STEP", "*Step", "*static", "0.01,1.0,1e-7,0.02", "*NODE FILE", "U",
                "*CONTACT FILE", "CDIS, CSTR", "*end step"]
    check(copy == expected, "the --lengthen-static copy:\n%s\nexpected:\n%s" % ("\n".join(copy), "\n".join(expected)))
    check(cc.prepared_deck(deck, None)[1:] == open(deck).read().splitlines()[1:], "a copy without "
          "--lengthen-static changes only the include path")
    # --add-output: the output added to every step, the *STATIC data lines kept (a shared deck on its own steps).
    added = cc.prepared_deck(deck, None, True)
    expected_added = [expected[0], "*STEP", "*STATIC", "** a comment", "0.001,0.001,1e-7,0.01", "*BOUNDARY", "N1,1,3",
                      "*NODE FILE", "U", "*CONTACT FILE", "CDIS, CSTR", "*END STEP", "*Step", "*static", "*NODE FILE",
                      "U", "*CONTACT FILE", "CDIS, CSTR", "*end step"]
    check(added == expected_added, "the --add-output copy:\n%s\nexpected:\n%s" % ("\n".join(added), "\n".join(expected_added)))

    # Usage errors: exit 2 before any work.
    stub = os.path.join(work, "stub")
    open(stub, "w").write("#!/bin/sh\nexit 0\n")
    os.chmod(stub, 0o755)
    frd_file = os.path.join(work, "long.frd")
    for args, text in ((["--frd", frd_file, "--run"], "either --frd"),
                       (["--run", "--lengthen-static", "1,2,3"], "4 positive numbers"),
                       (["--run", "--lengthen-static", "1,nan,3,4"], "4 positive numbers"),
                       (["--frd", frd_file, "--lengthen-static", "1,2,3,4"], "needs --run"),
                       (["--frd", frd_file, "--add-output"], "--add-output needs --run"),
                       (["--frd", frd_file, "--pair", "-1"], "--pair"),
                       (["--run", "--ccx-timeout", "nan"], "--ccx-timeout")):
        result = run([sys.executable, COMPARE, "--deck", deck, "--gen-configs", stub] + args, 2)
        check(text in result.stderr, "%s: message '%s' lacks '%s'" % (args, result.stderr.strip(), text))
    result = run([sys.executable, COMPARE, "--deck", deck, "--gen-configs", os.path.join(work, "none"), "--frd",
                  frd_file], 2)
    check("--gen-configs" in result.stderr, "a missing gen-configs: '%s'" % result.stderr.strip())
    print("frd-reader: long and short formats, touching values, continuation, COPEN per increment, 5 malformed "
          "files (exit 3, line named), --lengthen-static copy, usage errors (exit 2)")


# ---------------------------------------------------------------------------------------------------------
# make-scene-options
def make_scene_options_case(work):
    bad = [("hertz", ["--gap", "nan"], "--gap"), ("hertz", ["--gap", "inf"], "--gap"),
           ("hertz", ["--gap", "0.5"], "--gap"), ("forming", ["--jitter", "nan"], "--jitter"),
           ("flat", ["--jitter", "-0.01"], "--jitter"), ("cylinders", ["--radius", "nan"], "--radius"),
           ("cylinders", ["--radius", "0"], "--radius"), ("flat", ["--aspect", "inf"], "--aspect"),
           ("flat", ["--aspect", "0.5"], "--aspect"), ("hertz", ["--aspect", "2"], "--aspect"),
           ("hertz", ["--elements", "1"], "--elements"), ("hertz", ["--elements", "1000"], "--elements"),
           ("hertz", ["--seed", "-1"], "--seed"), ("all", ["--depth", "0.01"], "--depth"),
           ("hertz-slide", ["--depth", "nan"], "--depth"), ("hertz-slide", ["--depth", "0"], "--depth"),
           ("hertz-slide", ["--depth", "1"], "--depth"), ("hertz-slide", ["--slide", "-inf"], "--slide"),
           ("hertz-slide", ["--slide", "0.6"], "--slide"), ("forming-stroke", ["--slide", "0.1"], "--slide"),
           ("forming-stroke", ["--increments", "1"], "--increments"),
           ("forming-stroke", ["--elements", "17"], "--elements"),
           ("forming-stroke", ["--radius", "6"], "--radius"),
           ("forming-stroke", ["--gap", "-0.1", "--depth", "0.05"], "--gap + --depth"),
           ("histories", ["--aspect", "2"], "--aspect")]
    for kind, args, flag in bad:
        out = fresh(os.path.join(work, "out"))
        result = run([sys.executable, MAKE_SCENE, kind, "--output", out] + args, 2)
        check(flag in result.stderr, "make-scene %s %s: message '%s' does not name %s" %
              (kind, " ".join(args), result.stderr.strip(), flag))
        check(not os.listdir(out), "make-scene %s %s: wrote %s" % (kind, " ".join(args), os.listdir(out)))
    out = os.path.join(work, "never")
    run([sys.executable, MAKE_SCENE, "hertz", "--gap", "nan", "--output", out], 2)
    check(not os.path.exists(out), "make-scene with --gap nan created %s" % out)
    print("make-scene-options: %d bad options, each exit 2 naming it, nothing written" % len(bad))


# ---------------------------------------------------------------------------------------------------------
# Histories
def history(work, kind):
    """The deck of KIND with its defaults and its manifest; exit SKIP when ccx is not installed."""
    if shutil.which("ccx") is None:
        print("SKIP: ccx (CalculiX) is not installed; scripts/setup installs calculix-ccx")
        sys.exit(SKIP)
    scenes = fresh(os.path.join(work, "deck"))
    run([sys.executable, MAKE_SCENE, kind, "--output", scenes], 0)
    return os.path.join(scenes, kind + ".inp"), json.load(open(os.path.join(scenes, kind + ".json")))


def compare(work, deck, gen_configs, expect, extra=()):
    out = fresh(work)
    result = run([sys.executable, COMPARE, "--deck", deck, "--run", "--gen-configs", gen_configs, "--work", out,
                  "--output", os.path.join(out, "table.md")] + list(extra), expect)
    return result, out


def wrapper(work, perturb):
    """An executable that runs the reference search with --perturb."""
    path = os.path.join(work, "reference-%s" % (perturb or "plain"))
    with open(path, "w") as f:
        f.write("#!/bin/sh\nexec '%s' '%s' %s \"$@\"\n" % (sys.executable, REFERENCE,
                                                          "--perturb " + perturb if perturb else ""))
    os.chmod(path, 0o755)
    return path


def reference_case(work, kind):
    deck, manifest = history(work, kind)
    # 1. The reference search agrees with every contact.
    result, out = compare(os.path.join(work, "plain"), deck, wrapper(work, None), 0)
    print(result.stdout.strip())
    # 2. The history's shape: its increments, contacts in each, slave nodes crossing master face edges.
    cc = load_compare()
    frd = cc.Frd(os.path.join(out, kind + ".frd"))
    check(len(frd.increments) == manifest["increments"], "%d increments in the .frd, the manifest says %d" %
          (len(frd.increments), manifest["increments"]))
    per_increment = [sum(1 for c, _ in (inc["contact"] or {}).values() if c < 0) for inc in frd.increments]
    check(all(n > 0 for n in per_increment), "increments without a contact: %s" % per_increment)
    points, header = cc.read_points(os.path.join(out, "points.csv"))
    summary, _, failures = cc.compare(frd, points, True, os.path.basename(deck), 0, True)
    check(not failures, "failures: %s" % failures)
    edges = summary["crossings"].get("edge", 0)
    check(edges >= EDGE_CROSSINGS[kind], "%d moves across an edge to the next face, expected >= %d" %
          (edges, EDGE_CROSSINGS[kind]))
    check(set(k[1] for k in points) == set(manifest["pairs"][0]["slave_nodes"]),
          "the reference's slave nodes are not the manifest's")
    if kind in QUADRATIC:
        check_quadratic(kind, manifest, frd, points)
        print("reference:%s: %d increments, contacts per increment %s, %d edge crossings" %
              (kind, len(frd.increments), per_increment, edges))
        return
    # 3. A contact dropped, or every gap moved by 1e-3: exit 1 naming the contact.
    result, _ = compare(os.path.join(work, "drop"), deck, wrapper(work, "drop"), 1)
    check("found no point" in result.stderr, "drop: message '%s'" % result.stderr.strip()[:300])
    result, _ = compare(os.path.join(work, "offset"), deck, wrapper(work, "offset"), 1)
    check("beyond the bound" in result.stderr, "offset: message '%s'" % result.stderr.strip()[:300])
    # 4. Without the nodes column the bound is over every node of the file: still within it.
    compare(os.path.join(work, "nodes"), deck, wrapper(work, "nodes"), 0)
    print("reference:%s: %d increments, contacts per increment %s, %d edge crossings; dropped and offset "
          "points fail" % (kind, len(frd.increments), per_increment, edges))


def check_quadratic(kind, manifest, frd, points):
    """Every contact's point on a face of the history's quadratic type; mid-side slave nodes among the contacts
    where the slave surface is quadratic."""
    face_type, midside = QUADRATIC[kind]
    corners = set(manifest["pairs"][0].get("corner_slave_nodes", manifest["pairs"][0]["slave_nodes"]))
    contacts = [(index, nid) for index, inc in enumerate(frd.increments, start=1)
                for nid, (copen, _) in (inc["contact"] or {}).items() if copen < 0]
    types = {points[key]["face_type"] for key in contacts if key in points}
    check(types == {face_type}, "%s: contacts on faces %s, expected %s only" % (kind, sorted(types), face_type))
    at_midside = sum(1 for _, nid in contacts if nid not in corners)
    check(at_midside > 0 or not midside, "%s: no contact at a mid-side slave node" % kind)
    print("%s: every contact on a %s face; %d of %d contacts at mid-side slave nodes" %
          (kind, face_type, at_midside, len(contacts)))


def gen_configs_case(work, kind, gen_configs):
    deck, manifest = history(work, kind)
    result, out = compare(os.path.join(work, "compare"), deck, gen_configs, None)
    print(result.stdout.strip())
    if result.returncode != 0:
        raise Failure("calculix-compare: exit %d\n%s" % (result.returncode, result.stderr))
    if kind in QUADRATIC:
        cc = load_compare()
        points, _ = cc.read_points(os.path.join(out, "points.csv"))
        check_quadratic(kind, manifest, cc.Frd(os.path.join(out, kind + ".frd")), points)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--gen-configs")
    opts = parser.parse_args()
    work = fresh(os.path.join(opts.work, opts.case.replace(":", "-")))
    try:
        if opts.case == "frd-reader":
            frd_reader_case(work)
        elif opts.case == "make-scene-options":
            make_scene_options_case(work)
        elif opts.case.startswith("reference:"):
            reference_case(work, opts.case.split(":", 1)[1])
        elif opts.case.startswith("gen-configs:"):
            if not opts.gen_configs:
                parser.error("--case gen-configs:KIND needs --gen-configs PATH")
            gen_configs_case(work, opts.case.split(":", 1)[1], opts.gen_configs)
        else:
            parser.error("unknown --case %s" % opts.case)
    except Failure as e:
        print("FAIL: %s" % e, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
