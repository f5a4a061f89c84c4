#!/usr/bin/env python3
"""replay end to end on a CalculiX history (make-scene hertz-slide, run by ccx in about a second).

Checks: exit 0; increments.csv has one row per increment of the .frd; tracking gives the fresh search's
answers at every increment (tracking_differences 0), and so does the search before the certificate
(reference_differences 0); every contact CalculiX reports (COPEN < 0) has a point,
with |gap - COPEN| within the .frd's precision (1e-5 on this deck's coordinates of magnitude 2: see
scripts/calculix-compare); the warm start+newton:2 reaches the surface search's points to 1e-10 while
start+newton:0 (the previous point itself) does not; the cold newton:5 is exact; the same answers at 1 and 2
threads; report.md names every method; the three plots are well-formed XML with one polyline or more. Then a
results file of another deck is refused (exit 3, the file named). Skipped (77) without ccx.

Usage: replay_check.py --replay PATH --make-scene PATH --work DIR
"""
import csv
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import required_options  # noqa: E402  (tests/check_support.py)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(args, expect=0, cwd=None):
    r = subprocess.run(args, capture_output=True, text=True, cwd=cwd)
    if r.returncode != expect:
        fail("%s: exit %d, expected %d\n%s%s" % (" ".join(args), r.returncode, expect, r.stdout, r.stderr))
    return r


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def main():
    a = required_options("--replay", "--make-scene", "--work")
    if shutil.which("ccx") is None:
        print("ccx (calculix-ccx) is not installed: skipped")
        return 77
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    run([sys.executable, a.make_scene, "hertz-slide", "--output", a.work])
    run(["ccx", "-i", "hertz-slide"], cwd=a.work)
    deck, frd = os.path.join(a.work, "hertz-slide.inp"), os.path.join(a.work, "hertz-slide.frd")
    reports = {}
    for threads in (1, 2):
        report = os.path.join(a.work, "report-%d" % threads)
        run([a.replay, "--scene", deck, "--results", frd, "--report", report, "--threads", str(threads), "--quiet",
             "--repeats", "1"])
        reports[threads] = read(os.path.join(report, "increments.csv"))
    rows = reports[1]
    increments = sum(1 for line in open(frd) if line.startswith(" -4  DISP"))
    if len(rows) != increments:
        fail("%d rows in increments.csv for %d increments" % (len(rows), increments))
    contacts = 0
    for r in rows:
        if r["tracking_differences"] != "0":
            fail("increment %s: %s tracked answers differ from the fresh search" % (r["increment"], r["tracking_differences"]))
        if r.get("reference_differences", "0") != "0":
            fail("increment %s: %s answers differ from the reference search's" % (r["increment"], r["reference_differences"]))
        if r["calculix_contacts"] != r["calculix_found"]:
            fail("increment %s: %s CalculiX contacts, %s with a point" % (r["increment"], r["calculix_contacts"], r["calculix_found"]))
        if float(r["calculix_largest_difference"]) > 1e-5:
            fail("increment %s: |gap - COPEN| %s" % (r["increment"], r["calculix_largest_difference"]))
        contacts += int(r["calculix_contacts"])
        if r["newton:5:mean_error"] and float(r["newton:5:mean_error"]) > 1e-12:
            fail("increment %s: newton:5 mean error %s" % (r["increment"], r["newton:5:mean_error"]))
    if contacts < 50:
        fail("only %d CalculiX contacts in the history" % contacts)
    warm = [r for r in rows[1:] if int(r["start+newton:2:queries"]) > 0]
    if not warm or any(float(r["start+newton:2:mean_error"]) > 1e-10 for r in warm):
        fail("start+newton:2 does not reach 1e-10 on the kept faces: %s" % [r["start+newton:2:mean_error"] for r in warm])
    if all(float(r["start+newton:0:mean_error"]) <= 1e-10 for r in warm):
        fail("start+newton:0 (the previous point) is already exact: the history does not move")
    answers = ["increment", "found", "face", "edge", "vertex", "faces_changed", "tracking_differences",
               "calculix_found", "calculix_largest_difference", "newton:5:mean_error", "start+newton:2:mean_error"]
    for r1, r2 in zip(reports[1], reports[2]):
        for name in answers:
            if r1[name] != r2[name]:
                fail("increment %s: %s %s at 1 thread, %s at 2" % (r1["increment"], name, r1[name], r2[name]))
    report = os.path.join(a.work, "report-1")
    text = open(os.path.join(report, "report.md")).read()
    for method in ["newton:3", "newton:5", "closed_form", "closed_form+newton:2", "start+newton:0", "start+newton:3"]:
        if "| " + method + " |" not in text:
            fail("report.md has no row for %s" % method)
    for plot in ["time.svg", "error.svg", "locations.svg"]:
        root = ET.parse(os.path.join(report, plot)).getroot()
        if not root.findall("{http://www.w3.org/2000/svg}polyline"):
            fail("%s has no line" % plot)
    # A results file that belongs to another deck: exit 3, the file named.
    other = os.path.join(a.work, "other")
    run([sys.executable, a.make_scene, "forming-stroke", "--output", other])
    run(["ccx", "-i", "forming-stroke"], cwd=other)
    r = run([a.replay, "--scene", deck, "--results", os.path.join(other, "forming-stroke.frd"), "--report",
             os.path.join(a.work, "never")], expect=3)
    if "forming-stroke.frd" not in r.stderr or os.path.exists(os.path.join(a.work, "never", "report.md")):
        fail("mismatched results: %s" % r.stderr)
    print("replay on hertz-slide: %d increments, %d CalculiX contacts found, tracking exact, warm K = 2 exact" %
          (len(rows), contacts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
