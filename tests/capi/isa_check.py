#!/usr/bin/env python3
"""The instruction sets in libcontactnn_c (lib/search/isa_dispatch.hpp): a library built for any x86-64 holds no
AVX or AVX-512 instruction outside the kernel variants that the CPU check chooses.

Disassembles the library (objdump -d -w, which names every function, the variants' with their tag: isa_avx2,
isa_avx512, as a namespace or a clone suffix; cmake/contactnnIsolateObjects.cmake) and reads each instruction's
first opcode byte after any segment or address-size prefix: 0x62 is EVEX (AVX-512; BOUND is invalid in 64-bit
mode), 0xc4 and 0xc5 are VEX (AVX, AVX2, FMA; LES and LDS are invalid in 64-bit mode). Then:
  - EVEX only in functions of the avx512 variant, VEX only in those of the avx2 and avx512 variants;
  - every variant present, baseline with neither encoding, avx2 with VEX and no EVEX, avx512 with EVEX.

Usage: isa_check.py --objdump OBJDUMP --library LIB --variants baseline,avx2,avx512
Exit 0 passed, 1 failed, 77 skipped (a CONTACTNN_NATIVE build: everything is the build machine's).
"""
import collections
import re
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failures, required_options  # noqa: E402  (tests/check_support.py)

PREFIXES = {0x26, 0x2E, 0x36, 0x3E, 0x64, 0x65, 0x67}
FUNCTION = re.compile(r"^[0-9a-f]+ <(.+)>:$")
INSTRUCTION = re.compile(r"^\s*([0-9a-f]+):\t([0-9a-f ]+)\t(.*)$")


def encoding(raw):
    data = [int(b, 16) for b in raw.split()]
    i = 0
    while i < len(data) and data[i] in PREFIXES:
        i += 1
    if i >= len(data):
        return None
    if data[i] == 0x62:
        return "evex"
    if data[i] in (0xC4, 0xC5):
        return "vex"
    return None


def variant_of(function, variants):
    for v in variants:
        if "isa_" + v in function:
            return v
    return None


def main():
    a = required_options("--objdump", "--library", "--variants")
    variants = a.variants.split(",")
    if variants == ["native"]:
        print("a CONTACTNN_NATIVE build: compiled for the build machine throughout, nothing to check")
        return 77
    allowed = {"evex": {"avx512"}, "vex": {"avx2", "avx512"}}

    text = subprocess.run([a.objdump, "-d", "-w", a.library], capture_output=True, text=True, check=True).stdout
    function = "?"
    counts = collections.Counter()  # (variant or None, encoding)
    functions = collections.Counter()  # variant -> functions
    bad = collections.OrderedDict()  # function -> (encoding, address, instruction)
    for line in text.split("\n"):
        m = FUNCTION.match(line)
        if m:
            function = m.group(1)
            functions[variant_of(function, variants)] += 1
            continue
        m = INSTRUCTION.match(line)
        if not m:
            continue
        kind = encoding(m.group(2))
        if kind is None:
            continue
        variant = variant_of(function, variants)
        counts[(variant, kind)] += 1
        if variant not in allowed[kind] and function not in bad:
            bad[function] = (kind, m.group(1), m.group(3).strip())

    failures = []
    for function, (kind, address, instruction) in bad.items():
        failures.append(f"{kind.upper()} outside the {'/'.join(sorted(allowed[kind]))} variants: {function} "
                        f"at {address}: {instruction}")
    for v in variants:
        if functions[v] == 0:
            failures.append(f"no function of the {v} variant (isa_{v}) in the library")
    if "avx512" in variants and counts[("avx512", "evex")] == 0:
        failures.append("the avx512 variant has no AVX-512 instruction: not compiled for AVX-512?")
    if "avx2" in variants and counts[("avx2", "vex")] == 0:
        failures.append("the avx2 variant has no VEX instruction: not compiled for AVX2?")

    for v in variants + [None]:
        name = v or "the rest"
        print(f"{name:10s} {functions[v]:6d} functions, {counts[(v, 'vex')]:7d} VEX, {counts[(v, 'evex')]:7d} EVEX")
    reported = Failures(shown=40)  # after the table, as they were found
    for f in failures:
        reported.fail(f)
    return reported.exit_status("no AVX or AVX-512 instruction outside the kernel variants that need them")


if __name__ == "__main__":
    sys.exit(main())
