#!/usr/bin/env python3
"""The study scripts on tiny inputs: scripts/frontier and scripts/run-study run end to end on the current
evaluate-net and their outputs hold together.

  --case frontier   scripts/frontier on a configs/tiny.toml grid and a 300-row held-out sample with the
                    shipped 8-8-2 and short timing: the SVG is well-formed with one point per method per set and
                    a drawn front; the Markdown table's fastest-per-level rows agree with the numbers in the same
                    table (the oracle below, computed from the printed table alone); the oracle rejects a
                    table whose fastest row was tampered with (so the check can fail).
  --case run_study  scripts/run-study with a config written here (tiny grid, a short training, short timing):
                    the dataset, the network and the report with every method exist.
  --case scene_study  scripts/scene-study (the entry point of the compiled study, SPEC 7) on two example scenes
                    (--scenes: scripts/make-scene's) with small settings: its outputs (plan.toml, pairs.csv,
                    report.md, report.json; network.h5 exactly when the plan names it), a plan that reads as TOML
                    with the method and network the settings force, and scripts/scene-table over the studies.
Exit 0 on success; 1 with the reason otherwise.
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
import xml.etree.ElementTree as ET

LEVELS = ["0.1", "0.03", "0.01", "0.003", "0.001", "0.0001", "1e-08"]
# The table prints effective means with 3 significant digits and times with one decimal: a value within
# half a unit of the last printed digit of the level (or of another time) cannot be ordered from the table.
REL_ROUNDING = 5e-3
NS_ROUNDING = 0.05


class Failure(Exception):
    pass


def run(cmd, cwd):
    proc = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        raise Failure(f"exit {proc.returncode}: {' '.join(cmd)}\n{proc.stdout[-4000:]}")
    return proc.stdout


def cell_float(text):
    return float(text.replace("*", "").split("(")[0].strip())


def parse_sets(md):
    """{set: (methods, fastest)}: methods = [(name, bold, effective, batched_ns)], fastest = {level: name}."""
    sets = {}
    for block in re.split(r"^### Set `", md, flags=re.M)[1:]:
        name = block.split("`", 1)[0]
        methods, fastest, header, in_fastest = [], {}, None, False
        for line in block.splitlines():
            if not line.startswith("|"):
                header = None if not line.strip() else header
                continue
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip()[1:-1])]  # "\|" is a literal bar
            if cells[0] == "method":
                header, in_fastest = cells, False
                continue
            if cells[0].startswith("effective mean"):
                header, in_fastest = cells, True
                continue
            if set(cells[0]) <= set("-:"):
                continue
            if header is None:
                raise Failure(f"set {name}: table row without header: {line}")
            if in_fastest:
                fastest[cells[0]] = cells[1]
            else:
                row = dict(zip(header, cells))
                methods.append((row["method"].strip("*"), row["method"].startswith("**"),
                                cell_float(row["effective mean"]), cell_float(row["ns batched (min)"])))
        sets[name] = (methods, fastest)
    return sets


def fastest_violations(methods, fastest):
    """What in the fastest-per-level rows the method table contradicts (empty: consistent)."""
    problems = []
    by_name = {m[0]: m for m in methods}
    if sorted(fastest) != sorted(LEVELS):
        problems.append(f"levels {sorted(fastest)}, expected {sorted(LEVELS)}")
    for level_text, chosen in fastest.items():
        level = float(level_text)
        surely_in = [m for m in methods if m[2] < level * (1 - REL_ROUNDING)]
        if chosen == "none":
            if surely_in:
                problems.append(f"level {level_text}: 'none', but {surely_in[0][0]} has effective mean {surely_in[0][2]}")
            continue
        if chosen not in by_name:
            problems.append(f"level {level_text}: '{chosen}' is not in the method table")
            continue
        _, bold, eff, ns = by_name[chosen]
        if eff > level * (1 + REL_ROUNDING):
            problems.append(f"level {level_text}: '{chosen}' has effective mean {eff}, above the level")
        faster = [m for m in surely_in if m[3] < ns - NS_ROUNDING]
        if faster:
            problems.append(f"level {level_text}: '{chosen}' at {ns} ns, but {faster[0][0]} reaches it at {faster[0][3]} ns")
        # The fastest method at a level is never dominated, so it is on the front (bold).
        if not bold and not any(m[3] == ns and m[0] != chosen for m in methods):
            problems.append(f"level {level_text}: '{chosen}' is not marked as on the front")
    return problems


def check_frontier(a):
    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "out")
    log = run([sys.executable, os.path.join(a.source_dir, "scripts", "frontier"), "--surface", "bilinear",
               "--config", "configs/tiny.toml", "--grid", os.path.join(work, "tiny.h5"), "--random-count", "300",
               "--random-seed", "3", "--no-shipped", "--weights", "data/weights/bilinear-8.h5",
               "--timing-queries", "400", "--timing-repetitions", "3", "--timing-warmup", "0",
               "--build-dir", a.build, "--work", work, "--output", out, "--eval-threads", "2"], a.source_dir)
    md_path, svg_path = os.path.join(out, "frontier-bilinear.md"), os.path.join(out, "frontier-bilinear.svg")
    for p in (md_path, svg_path):
        if not os.path.isfile(p) or os.path.getsize(p) == 0:
            raise Failure(f"no output {p}\n{log[-3000:]}")
    with open(md_path) as f:
        md = f.read()
    sets = parse_sets(md)
    if sorted(sets) != ["tiny", "tiny-random-n300-s3"]:
        raise Failure(f"sets in the table: {sorted(sets)}")
    expected = {"network[bilinear-8]", "network+newton:3[bilinear-8]", "closed_form", "closed_form+newton:2",
                "newton:1", "newton:10", "newton"}
    for name, (methods, fastest) in sets.items():
        names = {m[0] for m in methods}
        if not expected <= names:
            raise Failure(f"set {name}: methods {sorted(expected - names)} missing from the table")
        problems = fastest_violations(methods, fastest)
        if problems:
            raise Failure(f"set {name}: fastest-per-level rows inconsistent with the table:\n  " + "\n  ".join(problems))
        # The oracle can fail: name, at the loosest level, the least accurate method instead.
        worst = max(methods, key=lambda m: m[2])
        if worst[2] <= 0.1 * (1 + REL_ROUNDING):
            raise Failure(f"set {name}: no method above 0.1 to tamper with (worst {worst})")
        if not fastest_violations(methods, dict(fastest, **{"0.1": worst[0]})):
            raise Failure(f"set {name}: the oracle accepted '{worst[0]}' (effective {worst[2]}) as fastest within 0.1")
        if fastest["0.1"] != "none" and not fastest_violations(methods, dict(fastest, **{"0.1": "none"})):
            raise Failure(f"set {name}: the oracle accepted 'none' at 0.1")

    root = ET.parse(svg_path).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    circles = root.findall(f"{ns}circle")
    points = sum(len(m) for m, _ in sets.values())
    legend = 4
    if len(circles) != points + legend:
        raise Failure(f"SVG: {len(circles)} circles, expected {points} points + {legend} legend marks")
    if len(root.findall(f"{ns}polyline")) != len(sets):
        raise Failure("SVG: not one drawn front per set")
    texts = {t.text for t in root.findall(f"{ns}text")}
    for name in ("network+newton:3[bilinear-8]", "closed_form", "newton"):
        if name not in texts:
            raise Failure(f"SVG: no label '{name}'")
    print(f"frontier: {len(sets)} sets, {points} points, fastest rows consistent")


def check_run_study(a):
    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(os.path.join(a.source_dir, "configs", "tiny.toml")) as f:
        gen = f.read()
    config = os.path.join(work, "tiny-study.toml")
    with open(config, "w") as f:
        f.write(gen + "\n[train-net]\nepochs = 20\ntrain_count = 100\n\n[evaluate-net]\ntiming_queries = 300\n"
                "timing_repetitions = 1\ntiming_warmup_passes = 0\n")
    data, report = os.path.join(work, "tiny.h5"), os.path.join(work, "report")
    log = run(["bash", os.path.join(a.source_dir, "scripts", "run-study"), "--config", config, "--build-dir", a.build,
               "--no-build", "--data", data, "--network", os.path.join(work, "tiny-net.h5"), "--report", report,
               "--threads", "2"], work)
    for p in (data, os.path.join(work, "tiny-net.h5"), os.path.join(report, "errors.csv"), os.path.join(report, "speed.csv"), os.path.join(report, "report.md")):
        if not os.path.isfile(p):
            raise Failure(f"run-study left no {p}\n{log[-3000:]}")
    with open(os.path.join(report, "report.md")) as f:
        md = f.read()
    for needle in ("network[tiny-net]", "closed_form+newton:1", "newton:10", "Fastest method at each accuracy level"):
        if needle not in md:
            raise Failure(f"report.md has no '{needle}'")
    if "The tiny-study study report:" not in log:
        raise Failure(f"run-study did not finish:\n{log[-2000:]}")
    print("run-study: dataset, network and report written")


SMALL = ["--count", "2000", "--epochs", "20", "--long-epochs", "0", "--timing-queries", "2000",
         "--timing-repetitions", "3", "--threads", "2", "--quiet"]


def check_scene_study(a):
    work = os.path.abspath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    script = os.path.join(a.source_dir, "scripts", "scene-study")
    flat, hertz = os.path.join(a.scenes, "flat.inp"), os.path.join(a.scenes, "hertz.inp")
    studies = {
        # (deck, pair, surface, extra options) -> what the plan must be
        "flat-0-bilinear": ((flat, "0", "bilinear", []), None),
        "hertz-0-gregory": ((hertz, "0", "gregory", ["--sizes", "16", "--train-networks", "always", "--methods",
                                                     "closed_form", "--network-methods", "network+newton:2"]),
                            "network+newton:2"),
    }
    for name, ((deck, pair, surface, extra), method) in studies.items():
        out = os.path.join(work, "table", name)
        log = run([sys.executable, script, "--scene", deck, "--pair", pair, "--surface", surface, "--output", out,
                   "--build-dir", a.build] + SMALL + extra, work)
        for f in ("plan.toml", "pairs.csv", "report.md", "report.json"):
            if not os.path.isfile(os.path.join(out, f)):
                raise Failure(f"{name}: scene-study left no {f}\n{log[-3000:]}")
        with open(os.path.join(out, "plan.toml"), "rb") as f:
            plan = tomllib.load(f)["plan"]
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        with open(os.path.join(out, "pairs.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        faces = sum(1 for r in rows if r["location"] == "face")
        if report["locations"]["face"] != faces:
            raise Failure(f"{name}: report.json counts {report['locations']['face']} face pairs, pairs.csv {faces}")
        if plan["method"] != report["plan"]["method"] or plan["surface"] != surface:
            raise Failure(f"{name}: plan.toml {plan} and report.json {report['plan']} disagree")
        network = os.path.join(out, "network.h5")
        if method is None:
            if plan["network"] or os.path.exists(network) or "network" in plan["method"]:
                raise Failure(f"{name}: a network in the plan of a flat scene: {plan}")
        else:
            if plan["method"] != method or plan["network"] != "network.h5" or not os.path.isfile(network):
                raise Failure(f"{name}: expected {method} with network.h5, got {plan}")
            run([os.path.join(a.build, "apps", "evaluate-net", "evaluate-net"), "--weights", network, "--input",
                 os.path.join(out, "pairs.csv"), "--output", os.path.join(work, "predicted.csv")], work)
    # scene-table over the same studies (reused: report.json is there).
    table = run([sys.executable, os.path.join(a.source_dir, "scripts", "scene-table"), "--output",
                 os.path.join(work, "table"), "--build-dir", a.build, "--surfaces", "bilinear", "--max-pairs", "1",
                 flat], work)
    row = next((l for l in table.splitlines() if l.startswith("| flat | 0 | bilinear |")), None)
    if row is None or "met" not in row:
        raise Failure(f"scene-table: no row for flat pair 0, or no verdict on the plan:\n{table}")
    print("scene-study: plans, pairs, reports and network as set; scene-table row: " + row)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", choices=["frontier", "run_study", "scene_study"], required=True)
    ap.add_argument("--scenes", help="scene_study: the example scenes of scripts/make-scene")
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--build", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    a.build = os.path.abspath(a.build)
    try:
        {"frontier": check_frontier, "run_study": check_run_study, "scene_study": check_scene_study}[a.case](a)
    except Failure as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
