#!/usr/bin/env python3
"""The installed C library under valgrind's memcheck, as a finite-element code's debugging run would load it.

Builds the C and Fortran consumer (tests/capi/consumer) against the INSTALLED package (PREFIX) in a fresh
directory, then runs search_c (double and float) and search_fortran on random queries of both surfaces (hostile
rows included: NaN, collapsed, far, tiny, huge) with several methods under
    valgrind --tool=memcheck --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite
(the Fortran main program's own arrays, which it never deallocates, suppressed), once with CONTACTNN_ISA=baseline
(the variant of a CPU without AVX2) and once with the library's own choice
(valgrind's virtual CPU has AVX2 and no AVX-512: the avx2 variant). Each run must end with status 0 and no
memcheck error, and write the same bytes as the same program outside valgrind with the same CONTACTNN_ISA: for
baseline the same code, unforced valgrind's avx2 against this CPU's own choice (avx512 on an AVX-512 machine),
which give the same bits as all variants with FMA do.

Exit 0 passed, 1 failed, 77 skipped (no valgrind).

Usage: consumer_valgrind.py --valgrind VALGRIND --cmake CMAKE --generator G --prefix PREFIX --project DIR --work DIR
                            --source-dir SRC --make-queries P [--set VAR=VALUE]...
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import consumer_check  # noqa: E402  (raw_text: RAW.csv -> the programs' input)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failures, add_consumer_options, build_consumer  # noqa: E402  (tests/check_support.py)

QUERIES = 60
MEMCHECK = ["--tool=memcheck", "--error-exitcode=99", "--leak-check=full", "--errors-for-leak-kinds=definite",
            "--show-leak-kinds=definite", "--num-callers=30"]
# The Fortran program's own arrays: allocatables of a main program are never deallocated (they live until the
# process ends), which memcheck calls definitely lost. Only blocks that MAIN__ itself allocated: a leak in the
# library has the library's functions on its stack.
FORTRAN_MAIN_SUPPRESSION = """{
   search_fortran main program allocatables
   Memcheck:Leak
   match-leak-kinds: definite
   fun:malloc
   fun:MAIN__
   fun:main
}
"""
failures = Failures()
fail = failures.fail


def run(command, env=None):
    return subprocess.run(command, capture_output=True, text=True, env=env)


def main():
    ap = argparse.ArgumentParser()
    add_consumer_options(ap)
    ap.add_argument("--project", required=True)
    ap.add_argument("--make-queries", required=True)
    a = ap.parse_args()
    valgrind = a.valgrind or shutil.which("valgrind")
    if not valgrind or not os.access(valgrind, os.X_OK):
        print("valgrind not found (Debian package valgrind; scripts/setup installs it): skipped")
        return 77

    # 1. The consumer, built against the installed package only.
    build, _ = build_consumer(a, a.project)

    suppressions = os.path.join(a.work, "fortran-main.supp")
    with open(suppressions, "w") as f:
        f.write(FORTRAN_MAIN_SUPPRESSION)

    # 2. Random queries of both surfaces, every seventh row hostile, values exact in float.
    cases = []
    for surface, network, seed in (("bilinear", "bilinear-32-32.h5", 21), ("gregory", "gregory-32.h5", 22)):
        csv = os.path.join(a.work, f"{surface}.csv")
        p = run([a.make_queries, surface, str(QUERIES), str(seed), csv])
        if p.returncode != 0:
            print(f"FAIL: {a.make_queries} exited {p.returncode}: {p.stderr}")
            return 1
        text = os.path.join(a.work, f"{surface}.txt")
        consumer_check.raw_text(csv, surface, text)
        cases.append((surface, os.path.join(a.source_dir, "data", "weights", network), text))

    # 3. Each program under memcheck, in the baseline variant and in the library's choice; then outside it.
    #    The network alone, a hybrid (network start, safeguarded Newton) and Newton to convergence (its passes
    #    over the pending lanes) take every kind of kernel: block, one-lane (the last rows), tie and pending rows.
    runs = [("search_c", "double", ["network", "network+newton:3", "newton"]),
            ("search_c", "float", ["network+newton:3"]),
            ("search_fortran", "double", ["network+newton:3"])]
    started = time.time()
    count = 0
    for isa in ("baseline", None):
        env = dict(os.environ)
        env.pop("CONTACTNN_ISA", None)
        if isa:
            env["CONTACTNN_ISA"] = isa
        label = isa or "the library's choice"
        for surface, network, text in cases:
            for program, precision, methods in runs:
                for method in methods:
                    name = f"{program} {precision} {surface} {method} ({label})"
                    out = os.path.join(a.work, f"{program}-{precision}-{surface}-{method}-{isa or 'auto'}")
                    args = [surface, method, network, text]
                    log = out + ".memcheck"
                    p = run([valgrind, *MEMCHECK, f"--suppressions={suppressions}", f"--log-file={log}", os.path.join(build, program), *args,
                             out + ".valgrind.txt", precision], env=env)
                    count += 1
                    if p.returncode != 0:
                        with open(log) as f:
                            report = f.read()
                        fail(f"{name}: exited {p.returncode} under memcheck (99: memcheck errors):\n"
                             f"{p.stdout}{p.stderr}\n{report[-6000:]}")
                        continue
                    q = run([os.path.join(build, program), *args, out + ".native.txt", precision], env=env)
                    if q.returncode != 0:
                        fail(f"{name}: exited {q.returncode} outside valgrind: {q.stdout}{q.stderr}")
                        continue
                    with open(out + ".valgrind.txt") as f:
                        under = f.read()
                    with open(out + ".native.txt") as f:
                        native = f.read()
                    # Unforced, valgrind's choice (avx2) against this CPU's (avx512 on an AVX-512 machine): the
                    # variants with FMA give the same bits.
                    if under != native:
                        fail(f"{name}: the output under valgrind differs from the output outside it")
                    print(f"{name:70s} memcheck: no error; output as outside valgrind")
    print(f"{count} runs under memcheck in {time.time() - started:.0f} s")
    return failures.exit_status("all checks passed")


if __name__ == "__main__":
    sys.exit(main())
