#!/usr/bin/env python3
"""The C, Fortran and C++ interfaces as a finite-element code gets them: from the INSTALLED package.

install:  `cmake --install BUILD` (components contactnn_runtime and contactnn_development) into an empty PREFIX,
          then checks what a consumer relies on: the C header and the Fortran module's source, the package
          config and version files, a libcontactnn_c that exports the contactnn_* functions and nothing else,
          and the exported C++ run-time target: contactnn::runtime's link closure in contactnnTargets.cmake
          holds none of the targets in NOT_RUNTIME_TARGETS (the trainer, lib/dataset, lib/mesh, the rest of
          lib/io, the tools' libraries, CLI11, toml++).
consumer: configures and builds a consumer project (tests/capi/consumer: C and Fortran; consumer_cxx: C++)
          against PREFIX in a fresh build directory (CMAKE_PREFIX_PATH=PREFIX only), checks that its programs
          load the installed libcontactnn_c and that none of contactnn's own build flags (-march=native, -O3)
          reached its compile commands; with --runtime-program P (the C++ consumer, linked to contactnn::runtime
          alone), that P's link command names none of the NOT_RUNTIME_LIBRARIES and that P defines none of the
          contactnn symbols that only those installed archives define (nm), nor a trainer, CLI11 or toml++
          symbol, while it does define LocalSearch's and read_network_model's; then runs each program on each case below and compares it with
          `evaluate-net --input` on the same RAW.csv:
            - statuses equal, row by row;
            - where evaluate-net writes a prediction (ok, out_of_domain), both coordinates within 1e-6 (the
              acceptance line of issue 11); float runs within 1e-6 of max(1, |value|) (a float holds 7 digits);
            - every output finite, iterations 0 (the network alone);
            - bilinear: the gap equals n.(S - P) at the reported point, recomputed here (P, n from the bilinear
              map in plain Python), within 1e-9 (double) or 1e-5 (float) of the segment size plus |gap|.
          Cases: the shipped examples (data/examples, data/weights) in double, and 300 random queries per
          surface from capi_make_queries (the paper's domains placed at random, hostile rows mixed in, values
          exact in float) in double and float.

Usage: consumer_check.py install --cmake CMAKE --build BUILD --prefix PREFIX
       consumer_check.py consumer --cmake CMAKE --generator G --prefix PREFIX --project DIR --work DIR
                         --programs NAME... --source-dir SRC --evaluate-net P --make-queries P [--set VAR=VALUE]...
                         [--runtime-program NAME]
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failures, build_consumer, run_or_exit  # noqa: E402  (tests/check_support.py)

POINT_COLUMNS = "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz".split(",")
NORMAL_COLUMNS = "nax,nay,naz,nbx,nby,nbz,ncx,ncy,ncz,ndx,ndy,ndz".split(",")
STATUS = {"ok": 0, "outside": 1, "no_convergence": 2, "degenerate": 3, "invalid": 4, "out_of_domain": 5,
          "no_segment": 6}
TOLERANCE = 1e-6           # predictions against evaluate-net (issue 11's acceptance line)
GAP_TOLERANCE_DOUBLE = 1e-9  # relative to segment size + |gap|: rounding of a few dozen operations
GAP_TOLERANCE_FLOAT = 1e-5   # a float gap and a float point: 7 digits, a few roundings

# What contactnn::runtime (the C++ local search and network file reader) must not link: the trainer
# (contactnn::mlp; the network itself is contactnn::network), lib/dataset, lib/mesh, the rest of lib/io, the
# tools' own libraries and the command-line layer. Targets as contactnnTargets.cmake names them, and the
# libraries' file stems.
NOT_RUNTIME_MODULES = ("mlp", "dataset", "mesh", "io", "contact", "eval", "plan_file", "study", "history", "cli")
NOT_RUNTIME_TARGETS = tuple("contactnn::" + m for m in NOT_RUNTIME_MODULES) + (
    "CLI11::CLI11", "tomlplusplus::tomlplusplus")
NOT_RUNTIME_LIBRARIES = tuple("libcontactnn_" + m for m in NOT_RUNTIME_MODULES)
# Demangled names that no part of the run-time target defines (the trainer's classes, the CLI's, toml++'s).
NOT_RUNTIME_SYMBOLS = re.compile(r"contactnn::mlp::(Trainer|OnlineBackprop|PatternBackprop|BatchGradient)\b|"
                                 r"contactnn::(dataset|mesh|contact|eval|study|history|cli)::|\bCLI::|\btoml::")
# ... and names it must define, so that the symbol check is not vacuous (a stripped or empty program).
RUNTIME_SYMBOLS = (r"contactnn::search::LocalSearch::run<double>\(", r"^contactnn::io::read_network_model\(")
# The archives contactnn::runtime does link (search, network_file and what they link).
RUNTIME_LIBRARIES = tuple("libcontactnn_" + m for m in ("search", "network_file", "network", "projection", "geometry",
                                                         "core"))

failures = Failures(shown=30)
check = failures.check
run = run_or_exit


def install(args):
    if os.path.exists(args.prefix):
        shutil.rmtree(args.prefix)
    for component in ("contactnn_runtime", "contactnn_development"):
        run([args.cmake, "--install", args.build, "--prefix", args.prefix, "--component", component])
    files = []
    for root, _, names in os.walk(args.prefix):
        files += [os.path.relpath(os.path.join(root, n), args.prefix) for n in names]
    for wanted in ("include/contactnn/contactnn.h", "include/contactnn/contactnn.f90",
                   "include/contactnn/search/local_search.hpp", "include/contactnn/io/network_file.hpp"):
        check(wanted in files, f"{wanted} is not installed")
    for suffix in ("contactnnConfig.cmake", "contactnnConfigVersion.cmake", "contactnnTargets.cmake"):
        check(any(f.endswith("cmake/contactnn/" + suffix) for f in files), f"{suffix} is not installed")
    check(not any("/eval/" in f or "/study/" in f or "/history/" in f for f in files),
          "the tools' own modules were installed")
    check("include/contactnn/contact/contact_search.hpp" in files, "contact::ContactSearch is not installed")
    libraries = [f for f in files if os.path.basename(f).startswith("libcontactnn_c.so.")
                 and not os.path.islink(os.path.join(args.prefix, f))]
    check(len(libraries) == 1, f"one libcontactnn_c.so.X.Y.Z expected, found {libraries}")
    if libraries:
        nm = run(["nm", "-D", "--defined-only", os.path.join(args.prefix, libraries[0])]).stdout.split("\n")
        symbols = [line.split()[-1] for line in nm if line.strip()]
        others = [s for s in symbols if not s.startswith("contactnn_")]
        check(len(symbols) > 0 and not others, f"libcontactnn_c exports more than the C interface: {others[:5]}")
        print(f"installed: {len(files)} files; libcontactnn_c exports {len(symbols)} symbols, all contactnn_*")
    targets = [f for f in files if f.endswith("cmake/contactnn/contactnnTargets.cmake")]
    if targets:
        check_runtime_closure(os.path.join(args.prefix, targets[0]))


def exported_links(targets_file):
    """contactnnTargets.cmake: each exported target's INTERFACE_LINK_LIBRARIES, as a list of names."""
    with open(targets_file) as f:
        text = f.read()
    links = {}
    for target, body in re.findall(r"set_target_properties\((\S+) PROPERTIES(.*?)\n\)", text, re.S):
        m = re.search(r'INTERFACE_LINK_LIBRARIES "([^"]*)"', body)
        if m:
            links[target] = [item for item in m.group(1).split(";") if item]
    return links


def check_runtime_closure(targets_file):
    """contactnn::runtime and everything it links (transitively, LINK_ONLY included) as the package exports
    them: none of NOT_RUNTIME_TARGETS."""
    links = exported_links(targets_file)
    check("contactnn::runtime" in links, f"{targets_file} exports no contactnn::runtime with link libraries")
    closure, stack = set(), ["contactnn::runtime"]
    while stack:
        target = stack.pop()
        for item in links.get(target, []):
            name = re.sub(r"^\\?\$<LINK_ONLY:(.*)>$", r"\1", item)  # written \$<LINK_ONLY:...> in the file
            if name not in closure:
                closure.add(name)
                stack.append(name)
    bad = sorted(closure.intersection(NOT_RUNTIME_TARGETS))
    check(not bad, f"contactnn::runtime links {bad} (its exported closure: {sorted(closure)})")
    print(f"contactnn::runtime links {sorted(closure)}")


def check_runtime_program(args, build, program, build_log):
    """A program linked to contactnn::runtime alone: its link command names none of NOT_RUNTIME_LIBRARIES, and
    it defines none of the contactnn symbols that only the installed archives of those modules define, none
    matching NOT_RUNTIME_SYMBOLS, and every one of RUNTIME_SYMBOLS."""
    link = [line for line in build_log.split("\n") if re.search(r"-o \S*\b" + re.escape(program) + r"(\s|$)", line)]
    check(len(link) == 1, f"{program}: one link command expected in the build log, found {len(link)}")
    for line in link:
        named = sorted({m for m in re.findall(r"libcontactnn_\w+", line) if m in NOT_RUNTIME_LIBRARIES})
        check(not named, f"{program} links {named}: {line}")
        check("libcontactnn_search" in line and "libcontactnn_network_file" in line,
              f"{program}'s link command lacks contactnn::runtime's libraries: {line}")

    def defined_names(path):
        names = set()
        for line in run(["nm", "-C", "--defined-only", path]).stdout.split("\n"):
            parts = line.split(maxsplit=2)
            if len(parts) == 3:
                names.add(parts[2])
        return names

    # Linked with hidden visibility, contactnn's functions are local symbols of the program: every defined one counts.
    names = defined_names(os.path.join(build, program))
    for wanted in RUNTIME_SYMBOLS:
        check(any(re.search(wanted, n) for n in names), f"{program} does not define {wanted}")
    bad = sorted(n for n in names if NOT_RUNTIME_SYMBOLS.search(n))
    check(not bad, f"{program} defines {len(bad)} symbols of the trainer, dataset, mesh or CLI: {bad[:5]}")
    # contactnn's symbols that the installed archives contactnn::runtime must not link define, and that none of
    # the archives it does link defines (inline functions of a header both use): a program that defines one has
    # linked an object of a forbidden archive.
    libdirs = [os.path.join(args.prefix, d) for d in ("lib", "lib64", "lib/x86_64-linux-gnu")]

    def archives(stems):
        return [os.path.join(d, stem + ".a") for d in libdirs for stem in stems
                if os.path.exists(os.path.join(d, stem + ".a"))]
    forbidden_archives = archives(NOT_RUNTIME_LIBRARIES)
    runtime_archives = archives(RUNTIME_LIBRARIES)
    check(any(a.endswith("libcontactnn_mlp.a") for a in forbidden_archives), f"no libcontactnn_mlp.a under {libdirs}")
    check(len(runtime_archives) == len(RUNTIME_LIBRARIES), f"the run-time archives: {runtime_archives}")
    theirs = set()
    for archive in forbidden_archives:
        theirs |= {n for n in defined_names(archive) if "contactnn::" in n}
    for archive in runtime_archives:
        theirs -= defined_names(archive)
    linked = sorted(names & theirs)
    check(not linked, f"{program} defines {len(linked)} symbols of "
                      f"{[os.path.basename(a) for a in forbidden_archives]}: {linked[:5]}")
    print(f"{program}: link command free of {', '.join(NOT_RUNTIME_LIBRARIES)}; "
          f"{len(names)} symbols defined, none of the {len(theirs)} contactnn symbols only their archives define")


def raw_text(csv_path, surface, out_path):
    """RAW.csv -> the programs' plain format: the count, then one row of 15 or 27 numbers per query."""
    columns = POINT_COLUMNS + (NORMAL_COLUMNS if surface == "gregory" else [])
    with open(csv_path, newline="") as f:
        rows = [[float(r[c]) for c in columns] for r in csv.DictReader(f)]
    with open(out_path, "w") as f:
        f.write(f"{len(rows)}\n")
        for r in rows:
            f.write(" ".join(repr(x) for x in r) + "\n")
    return rows


def read_predictions(path, surface):
    names = ("xi", "eta") if surface == "bilinear" else ("u", "v")
    with open(path, newline="") as f:
        return [(r[names[0]], r[names[1]], STATUS[r["status"]]) for r in csv.DictReader(f)]


def read_output(path):
    rows = []
    with open(path) as f:
        for line in f:
            p0, p1, status, gap, iterations = line.split()
            rows.append((float(p0), float(p1), int(status), float(gap), int(iterations)))
    return rows


def sub(p, q):
    return [p[k] - q[k] for k in range(3)]


def bilinear_gap(raw, xi, eta):
    """n.(S - P) at (xi, eta) of the bilinear facet A B C D (SPEC 1, 2), n = unit(P_xi x P_eta)."""
    a, b, c, d, s = (raw[3 * i:3 * i + 3] for i in range(5))
    shape = [(1 - xi) * (1 - eta) / 4, (1 + xi) * (1 - eta) / 4, (1 + xi) * (1 + eta) / 4, (1 - xi) * (1 + eta) / 4]
    p = [sum(w * x[k] for w, x in zip(shape, (a, b, c, d))) for k in range(3)]
    p_xi = [((b[k] - a[k]) * (1 - eta) + (c[k] - d[k]) * (1 + eta)) / 4 for k in range(3)]
    p_eta = [((d[k] - a[k]) * (1 - xi) + (c[k] - b[k]) * (1 + xi)) / 4 for k in range(3)]
    n = [p_xi[1] * p_eta[2] - p_xi[2] * p_eta[1], p_xi[2] * p_eta[0] - p_xi[0] * p_eta[2],
         p_xi[0] * p_eta[1] - p_xi[1] * p_eta[0]]
    length = math.sqrt(sum(x * x for x in n))
    size = max(math.dist(a, b), math.dist(b, c), math.dist(c, d), math.dist(d, a))
    if length == 0 or not math.isfinite(length):
        return None, size
    return sum(n[k] / length * (s[k] - p[k]) for k in range(3)), size


def compare(name, surface, raw, reference, output, precision):
    check(len(output) == len(reference), f"{name}: {len(output)} rows, evaluate-net wrote {len(reference)}")
    worst = 0.0
    for i, (ref, got) in enumerate(zip(reference, output)):
        row = f"{name} row {i + 1}"
        p0, p1, status, gap, iterations = got
        check(status == ref[2], f"{row}: status {status}, evaluate-net {ref[2]}")
        check(all(math.isfinite(v) for v in (p0, p1, gap)), f"{row}: a non-finite output {got}")
        check(iterations == 0, f"{row}: {iterations} iterations for the network alone")
        if ref[0] != "" and status == ref[2]:
            for got_value, ref_value in ((p0, float(ref[0])), (p1, float(ref[1]))):
                scale = max(1.0, abs(ref_value)) if precision == "float" else 1.0
                error = abs(got_value - ref_value) / scale
                worst = max(worst, error)
                check(error <= TOLERANCE, f"{row}: {got_value!r} against evaluate-net's {ref_value!r}")
        if surface == "bilinear" and status in (STATUS["ok"], STATUS["out_of_domain"]):
            expected, size = bilinear_gap(raw[i], p0, p1)
            if expected is not None:
                tolerance = GAP_TOLERANCE_FLOAT if precision == "float" else GAP_TOLERANCE_DOUBLE
                check(abs(gap - expected) <= tolerance * (size + abs(expected)),
                      f"{row}: gap {gap!r}, recomputed {expected!r}")
        if status in (STATUS["invalid"], STATUS["degenerate"]):
            check(gap == 0.0, f"{row}: gap {gap!r} for status {status}, expected 0")
    return worst


def consumer(args):
    # 1. A fresh build of the consumer project against the installed package only.
    build, build_log = build_consumer(args, args.project, ["-DCMAKE_EXPORT_COMPILE_COMMANDS=ON"], ["--verbose"])
    with open(os.path.join(build, "compile_commands.json")) as f:
        commands = [entry["command"] for entry in json.load(f)]
    for command in commands:
        check("-march" not in command and "-O3" not in command,
              f"contactnn's build flags reached the consumer: {command}")
        if command.split()[0].endswith(("c++", "g++", "clang++")):
            check("EIGEN_MAX_ALIGN_BYTES=64" in command, f"the C++ consumer lacks Eigen's alignment setting: {command}")
    prefix = os.path.realpath(args.prefix)
    for program in args.programs:
        ldd = run(["ldd", os.path.join(build, program)]).stdout
        for line in ldd.split("\n"):
            if "libcontactnn_c" in line:
                check(prefix in os.path.realpath(line.split("=>")[1].split()[0]),
                      f"{program} loads {line.strip()}, not the installed library under {prefix}")
    if args.runtime_program:
        check_runtime_program(args, build, args.runtime_program, build_log)

    # 2. The cases: shipped examples, and random queries exact in float.
    source = args.source_dir
    cases = [("examples-bilinear", "bilinear", f"{source}/data/weights/bilinear-8.h5",
              f"{source}/data/examples/raw-bilinear.csv", ["double"]),
             ("examples-gregory", "gregory", f"{source}/data/weights/gregory-48.h5",
              f"{source}/data/examples/raw-gregory.csv", ["double"])]
    for surface, network, seed in (("bilinear", "bilinear-32-32.h5", 11), ("gregory", "gregory-32.h5", 12)):
        path = os.path.join(args.work, f"random-{surface}.csv")
        run([args.make_queries, surface, "300", str(seed), path])
        cases.append((f"random-{surface}", surface, f"{source}/data/weights/{network}", path, ["double", "float"]))

    # 3. Every program on every case, against evaluate-net.
    for name, surface, network, raw_csv, precisions in cases:
        predictions = os.path.join(args.work, f"{name}-evaluate-net.csv")
        run([args.evaluate_net, "--weights", network, "--input", raw_csv, "--output", predictions])
        reference = read_predictions(predictions, surface)
        text = os.path.join(args.work, f"{name}.txt")
        raw = raw_text(raw_csv, surface, text)
        statuses = sorted({r[2] for r in reference})
        for program in args.programs:
            for precision in precisions:
                if program == "search_cxx" and precision == "float":
                    continue
                out = os.path.join(args.work, f"{name}-{program}-{precision}.txt")
                command = [os.path.join(build, program), surface, "network", network, text, out]
                if program != "search_cxx":
                    command.append(precision)
                p = run(command)
                if program == "search_fortran":
                    check("shape check: ok" in p.stdout, f"search_fortran's shape check: {p.stdout}")
                    check("warm start: ok" in p.stdout, f"search_fortran's warm start: {p.stdout}")
                worst = compare(f"{name} {program} {precision}", surface, raw, reference, read_output(out), precision)
                print(f"{name:18s} {program:15s} {precision:6s} {len(reference):4d} rows, statuses {statuses}, "
                      f"max |difference| with evaluate-net {worst:.2e}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mode", choices=["install", "consumer"])
    parser.add_argument("--cmake", required=True)
    parser.add_argument("--build")
    parser.add_argument("--prefix", required=True)
    parser.add_argument("--generator")
    parser.add_argument("--project")
    parser.add_argument("--work")
    parser.add_argument("--programs", nargs="+", default=[])
    parser.add_argument("--source-dir")
    parser.add_argument("--evaluate-net")
    parser.add_argument("--make-queries")
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--runtime-program")
    args = parser.parse_args()
    if args.mode == "install":
        install(args)
    else:
        consumer(args)
    return failures.exit_status("all checks passed")


if __name__ == "__main__":
    sys.exit(main())
