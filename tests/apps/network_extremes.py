#!/usr/bin/env python3
"""Networks at the extremes (issue 5, part 2), through the stable command-line interface (SPEC 6).

1. gen-configs (configs/tiny.toml) -> data.h5; train-net -> net.h5 and its C header net.h (--export-header).
2. A suite of configurations in world coordinates: paper-domain configurations and ones far outside the
   training domain (slave 1e3 element sizes away, behind the segment, an interior angle of 179.9 degrees,
   aspect ratio 1e3, ...), collapsed segments and non-finite values, each unchanged and at scales 1e-6 ..
   1e6, randomly rotated and translated by 1e5 element sizes.
3. evaluate-net --input suite.csv: every prediction finite (or empty for invalid/degenerate); the
   configurations built outside the domain are flagged out_of_domain; the in-domain ones are not all
   flagged; status and prediction are the same at every scale, rotation and translation (float network:
   2e-5); invalid and degenerate rows say so.
4. The exported header, compiled with the C compiler (C99, -lm) and run on the same suite, returns the same
   status (0 ok, 1 invalid or degenerate, 2 out of domain) and the same prediction (to 1e-6).

Usage: network_extremes.py --gen-configs P --train-net P --evaluate-net P --cc CC --source-dir DIR --work DIR
"""
import argparse
import csv
import math
import os
import random
import shutil
import subprocess
import sys

COLUMNS = "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz".split(",")
STATUS_CODE = {"ok": 0, "invalid": 1, "degenerate": 1, "out_of_domain": 2}


def run(command, cwd):
    p = subprocess.run(command, cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"FAIL: {' '.join(command)} exited {p.returncode}:\n{p.stderr}")
    return p


def rotation(rng):
    q = [rng.gauss(0, 1) for _ in range(4)]
    n = math.sqrt(sum(x * x for x in q))
    w, x, y, z = (c / n for c in q)
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def transform(points, r, scale, t):
    return [[scale * sum(r[i][k] * p[k] for k in range(3)) + t[i] for i in range(3)] for p in points]


def paper_configuration(rng):
    """A configuration of the bilinear study (paper Section 5.1) in the normalised frame."""
    while True:
        c = [rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-0.2, 0.2)]
        d = [rng.uniform(-0.9, 0.9), rng.uniform(0.2, 0.95), 0.0]
        s = [rng.uniform(0.0, 0.9), rng.uniform(0.0, 0.9), rng.uniform(-0.2, 0.2)]
        a, b = [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]
        nodes = [a, b, c, d]
        if math.hypot(d[0], d[1]) > 1.0:
            continue
        # strictly convex, counter-clockwise in the xy-plane
        ok = True
        for i in range(4):
            p, nx, pv = nodes[i], nodes[(i + 1) % 4], nodes[(i + 3) % 4]
            cross = (nx[0] - p[0]) * (pv[1] - p[1]) - (nx[1] - p[1]) * (pv[0] - p[0])
            ok = ok and cross > 0.05
        dist = [sum((s[k] - n[k]) ** 2 for k in range(3)) for n in nodes]
        if ok and dist[0] <= min(dist[1:]):
            return nodes + [s]


def suite(rng):
    """(name, expectation, points) with expectation 'in' (drawn from the paper's domain), 'out' (built
    outside it), 'any' (no expectation on the domain flag), 'invalid', 'degenerate'."""
    cases = [(f"paper_{k}", "in", paper_configuration(rng)) for k in range(60)]
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    cases += [
        ("slave_1e3_above", "out", square + [[0.2, 0.1, 1e3]]),
        ("slave_1e3_behind", "out", square + [[0.2, 0.1, -1e3]]),
        ("slave_1e3_sideways", "out", square + [[1e3, 0.5, 0.0]]),
        ("slave_behind_z_-1", "out", square + [[0.3, 0.2, -1.0]]),
        # Inside the declared domain (feature box of the grid cells, filters): predicted, not flagged.
        ("angle_179.9_at_A", "any", [[0, 0, 0], [1, 0, 0], [0, 1, 0.05],
                                     [math.cos(math.radians(179.9)), math.sin(math.radians(179.9)), 0], [0.1, 0.1, 0.1]]),
        ("aspect_1e3", "any", [[0, 0, 0], [1, 0, 0], [1, 1e-3, 0], [0, 1e-3, 0], [0.4, 5e-4, 0.1]]),
        ("AD_1e3_longer", "out", [[0, 0, 0], [1, 0, 0], [1, 1e3, 0], [0, 1e3, 0], [0.3, 0.2, 0.1]]),
        ("C_far_out", "out", [[0, 0, 0], [1, 0, 0], [50, 40, 30], [0, 1, 0], [0.3, 0.2, 0.1]]),
        ("collapsed_A_B", "degenerate", [[0, 0, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0], [0.3, 0.2, 0.1]]),
        ("collinear", "degenerate", [[0, 0, 0], [1, 0, 0], [3, 0, 0], [2, 0, 0], [0.3, 0.2, 0.1]]),
    ]
    for k, bad in enumerate(["nan", "inf", "-inf"]):
        points = [p[:] for p in square] + [[0.3, 0.2, 0.1]]
        points[k % 5][k % 3] = float(bad)
        cases.append((f"non_finite_{bad}", "invalid", points))
    return cases


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    for tool in ("gen-configs", "train-net", "evaluate-net"):
        parser.add_argument("--" + tool, required=True)
    parser.add_argument("--cc", default="cc")
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--work", required=True)
    a = parser.parse_args()
    work = os.path.abspath(a.work)
    a.source_dir = os.path.abspath(a.source_dir)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    tools = {k: os.path.abspath(getattr(a, k.replace("-", "_"))) for k in ("gen-configs", "train-net", "evaluate-net")}
    failures = []

    # 1. A small trained network and its C header.
    run([tools["gen-configs"], "--config", os.path.join(a.source_dir, "configs", "tiny.toml"), "--output", "data.h5",
         "--quiet"], work)
    run([tools["train-net"], "--data", "data.h5", "--output", "net.h5", "--epochs", "200", "--train_count", "300",
         "--seed", "1", "--export-header", "net.h", "--quiet"], work)

    # 2. The suite, at every scale, rotation and translation.
    rng = random.Random(2007)
    rows = []
    placements = [("unit", 1.0, None, 0.0)]
    for scale in (1e-6, 1e-3, 1e3, 1e6):
        placements.append((f"scale {scale:g}", scale, rotation(rng), 0.0))
        placements.append((f"scale {scale:g} translated 1e5", scale, rotation(rng), 1e5))
    identity = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    for name, expect, points in suite(rng):
        for placement, scale, r, shift in placements:
            t = [shift * scale * v for v in (0.48, -0.6, 0.64)]
            world = transform(points, r or identity, scale, t)
            rows.append({"case": name, "expect": expect, "placement": placement,
                         "values": [v for p in world for v in p]})
    with open(os.path.join(work, "suite.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "expect", "placement"] + COLUMNS)
        for row in rows:
            w.writerow([row["case"], row["expect"], row["placement"]] + [repr(v) for v in row["values"]])
    with open(os.path.join(work, "suite.txt"), "w") as f:
        for row in rows:
            f.write(" ".join(repr(v) for v in row["values"]) + "\n")

    # 3. evaluate-net on the suite.
    run([tools["evaluate-net"], "--weights", "net.h5", "--input", "suite.csv", "--output", "pred.csv"], work)
    with open(os.path.join(work, "pred.csv"), newline="") as f:
        pred = list(csv.DictReader(f))
    if len(pred) != len(rows):
        failures.append(f"pred.csv has {len(pred)} rows for {len(rows)} inputs")
    by_case = {}
    in_domain = 0
    for row, p in zip(rows, pred):
        where = f"{row['case']} at {row['placement']}"
        status = p["status"]
        xi, eta = p["xi"], p["eta"]
        if status in ("ok", "out_of_domain"):
            try:
                values = (float(xi), float(eta))
            except ValueError:
                failures.append(f"{where}: prediction '{xi}', '{eta}' is not a number")
                continue
            if not all(math.isfinite(v) for v in values):
                failures.append(f"{where}: non-finite prediction {values}")
        elif status in ("invalid", "degenerate"):
            if xi or eta:
                failures.append(f"{where}: {status} row carries a prediction '{xi}', '{eta}'")
            values = None
        else:
            failures.append(f"{where}: unexpected status '{status}'")
            continue
        expect = row["expect"]
        if expect == "out" and status != "out_of_domain":
            failures.append(f"{where}: built outside the training domain, evaluate-net says '{status}'")
        if expect in ("invalid", "degenerate") and status != expect:
            failures.append(f"{where}: expected {expect}, evaluate-net says '{status}'")
        if expect == "in" and status == "ok" and row["placement"] == "unit":
            in_domain += 1
        first = by_case.setdefault(row["case"], (status, values, row["placement"]))
        if status != first[0]:
            failures.append(f"{where}: status '{status}', but '{first[0]}' at {first[2]}")
        elif values and first[1] and max(abs(values[0] - first[1][0]), abs(values[1] - first[1][1])) > 2e-5:
            failures.append(f"{where}: prediction {values} differs from {first[1]} at {first[2]}")
    if in_domain < 10:
        failures.append(f"only {in_domain} of 60 paper-domain configurations are inside the training domain: "
                        "the domain check flags (nearly) everything")

    # 4. The exported C header on the same suite.
    harness = os.path.join(work, "harness.c")
    with open(harness, "w") as f:
        f.write('#include <stdio.h>\n#include <stdlib.h>\n#include "net.h"\n'
                "int main(void) {\n  double raw[15], out[2];\n  char word[64];\n"
                "  for (;;) {\n    for (int i = 0; i < 15; ++i) {\n"
                "      if (scanf(\"%63s\", word) != 1) return 0;\n      raw[i] = strtod(word, NULL);\n    }\n"
                "    out[0] = out[1] = 0.0 / 0.0;\n    const int status = net_local_coordinates(raw, out);\n"
                "    printf(\"%d %.17g %.17g\\n\", status, out[0], out[1]);\n  }\n}\n")
    run([a.cc, "-std=c99", "-O2", "-Wall", "-Werror", "-o", "harness", "harness.c", "-lm"], work)
    with open(os.path.join(work, "suite.txt")) as f:
        p = subprocess.run([os.path.join(work, "harness")], stdin=f, capture_output=True, text=True, cwd=work)
    lines = p.stdout.splitlines()
    if p.returncode != 0 or len(lines) != len(rows):
        failures.append(f"the C harness exited {p.returncode} with {len(lines)} lines for {len(rows)} inputs")
    for row, pr, line in zip(rows, pred, lines):
        where = f"{row['case']} at {row['placement']} (C header)"
        code, x, y = line.split()
        if int(code) != STATUS_CODE.get(pr["status"], -1):
            failures.append(f"{where}: returns {code}, evaluate-net says '{pr['status']}'")
            continue
        if int(code) in (0, 2):
            if abs(float(x) - float(pr["xi"])) > 1e-6 or abs(float(y) - float(pr["eta"])) > 1e-6:
                failures.append(f"{where}: ({x}, {y}) vs evaluate-net ({pr['xi']}, {pr['eta']})")

    print(f"network extremes: {len(rows)} predictions ({len(by_case)} cases x {len(placements)} placements), "
          f"{in_domain}/60 paper-domain cases inside the training domain, {len(failures)} failures")
    for message in failures[:40]:
        print("FAIL " + message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
