#!/usr/bin/env python3
"""replay --plan and gen-configs --scene --plan end to end (issue 38, the plan in the loop), on a small history of
scripts/make-large-history (a prescribed motion, no solver), with plan files written here:

  - replay --plan: increments.csv has the plan's columns, no slave point refused, every found slave point answered,
    the plan's error within its target at every increment; --method the same;
  - gen-configs --scene --plan: the same faces and locations as without the plan, points to 1e-9;
  - the errors' exit codes (docs/tools.md): a malformed plan 3, a missing one 2, --surface against the plan's 2,
    a method the search cannot run 2, --plan with --method 2.
"""
import csv
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import required_options  # noqa: E402  (tests/check_support.py)

PLAN = """[plan]
schema_version = 1
surface = "bilinear"
method = "%s"
network = ""
target = 0.005
margin = 0.8
reached = true
[domain]
deck = "large.inp"
pair = 0
deformation = 0.1
capture = 0.5
normal_tilt_tangent = 0.1
boundary_fraction = 0.2
heldout_count = 100
heldout_seed = 1001
"""


def run(command, expect=0):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != expect:
        sys.exit("plan_check: %s: exit %d, expected %d\n%s%s" % (" ".join(command), result.returncode, expect,
                                                                  result.stdout, result.stderr))
    return result


def check_replay_csv(path, label):
    rows = list(csv.DictReader(open(path)))
    if not rows:
        sys.exit("plan_check: %s: no increments" % label)
    for r in rows:
        found, by_method, fallbacks = int(r["found"]), int(r["plan:by_method"]), int(r["plan:fallbacks"])
        if int(r["plan:refused"]) != 0:
            sys.exit("plan_check: %s increment %s: %s refused" % (label, r["increment"], r["plan:refused"]))
        if by_method == 0 or by_method + fallbacks > found:
            sys.exit("plan_check: %s increment %s: %d by the method, %d fallbacks of %d found" %
                     (label, r["increment"], by_method, fallbacks, found))
        if float(r["plan:mean_error"]) > 0.005:
            sys.exit("plan_check: %s increment %s: mean error %s" % (label, r["increment"], r["plan:mean_error"]))
        for column in ("ns_fresh", "ns_tracked", "newton:3:ns"):  # the existing columns keep their names
            if column not in r:
                sys.exit("plan_check: %s: no column %s" % (label, column))


def pairs(path):
    return {r["slave"]: r for r in csv.DictReader(open(path))}


def main():
    a = required_options("--replay", "--gen-configs", "--make-large-history", "--work")
    os.makedirs(a.work, exist_ok=True)
    run([sys.executable, a.make_large_history, "--output", a.work, "--slaves", "60", "--faces", "24", "--increments",
         "3"])
    deck, frd = os.path.join(a.work, "large.inp"), os.path.join(a.work, "large.frd")
    plan = os.path.join(a.work, "plan.toml")
    open(plan, "w").write(PLAN % "newton:3")
    report = os.path.join(a.work, "report")
    run([a.replay, "--scene", deck, "--results", frd, "--plan", plan, "--report", report, "--repeats", "1",
         "--quiet"])
    check_replay_csv(os.path.join(report, "increments.csv"), "--plan")
    if "## The plan in the loop" not in open(os.path.join(report, "report.md")).read():
        sys.exit("plan_check: report.md has no plan section")
    run([a.replay, "--scene", deck, "--results", frd, "--method", "closed_form+newton:2", "--report", report,
         "--repeats", "1", "--quiet"])
    check_replay_csv(os.path.join(report, "increments.csv"), "--method")

    # gen-configs --scene --plan: the exact search's faces and locations (newton:3 on these faces), points close.
    exact_csv, plan_csv = os.path.join(a.work, "exact.csv"), os.path.join(a.work, "plan.csv")
    run([a.gen_configs, "--scene", deck, "--output", exact_csv])
    run([a.gen_configs, "--scene", deck, "--plan", plan, "--output", plan_csv])
    exact, planned = pairs(exact_csv), pairs(plan_csv)
    if exact.keys() != planned.keys():
        sys.exit("plan_check: gen-configs --plan wrote other slave nodes")
    for node, e in exact.items():
        q = planned[node]
        for key in ("status", "location", "a", "b", "c", "d"):
            if key in e and e[key] != q[key]:
                sys.exit("plan_check: slave %s: %s %s against %s" % (node, key, q[key], e[key]))
        for key in ("px", "py", "pz"):
            if key in e and e[key] and abs(float(e[key]) - float(q[key])) > 1e-9:
                sys.exit("plan_check: slave %s: %s %s against %s" % (node, key, q[key], e[key]))

    # Errors and their exit codes.
    bad = os.path.join(a.work, "bad.toml")
    open(bad, "w").write("[plan]\nschema_version = 1\nsurface = \"bilinear\"\n")  # required keys missing
    out = os.path.join(a.work, "error.csv")
    run([a.gen_configs, "--scene", deck, "--plan", bad, "--output", out], expect=3)
    run([a.gen_configs, "--scene", deck, "--plan", os.path.join(a.work, "absent.toml"), "--output", out], expect=2)
    run([a.gen_configs, "--scene", deck, "--surface", "gregory", "--plan", plan, "--output", out], expect=2)
    start = os.path.join(a.work, "start.toml")
    open(start, "w").write(PLAN % "start+newton:1")
    run([a.gen_configs, "--scene", deck, "--plan", start, "--output", out], expect=2)
    run([a.replay, "--scene", deck, "--results", frd, "--plan", bad, "--report", report, "--quiet"], expect=3)
    run([a.replay, "--scene", deck, "--results", frd, "--plan", plan, "--method", "newton:2", "--report", report,
         "--quiet"], expect=2)
    print("plan_check: replay --plan, --method and gen-configs --plan as expected")


if __name__ == "__main__":
    main()
