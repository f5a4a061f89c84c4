#!/usr/bin/env python3
"""Networks at the extremes (issue 5, part 2), through the stable command-line interface (SPEC 6).

For the bilinear facet (--surface bilinear, the default) or the Gregory patch (--surface gregory):
1. A tiny dataset and a small trained network with its C header net.h (train-net --export-header):
   bilinear: gen-configs --config configs/tiny.toml; gregory: gen-configs --config configs/gregory-paper.toml
   on a coarse grid (command-line overrides: ~830 rows, 3 node-normal sets per configuration).
2. A suite of configurations in world coordinates: paper-domain configurations and ones far outside the
   training domain (slave 1e3 element sizes away, behind the segment, an interior angle of 179.9 degrees,
   aspect ratio 1e3, ...), collapsed segments and non-finite values, each unchanged and at scales 1e-6 ..
   1e6, randomly rotated and translated by 1e5 element sizes. Gregory adds node normals (rotated with the
   placement, never scaled or translated): paper-domain ones (interior angles in [60, 120] degrees, each
   normal tilted from the segment's corner normal by an angle of tangent below 0.2); a normal tilted by 45
   degrees or almost in the segment plane (out of domain); a normal in the segment plane, one flipped to the
   other side and a zero normal (degenerate); NaN / inf in a normal component (invalid); and a paper
   configuration with node normals of length 1e-300, 1e300 and 7.5 instead of 1 (SPEC 6: any positive length).
3. evaluate-net --input suite.csv: every prediction finite (or empty for invalid/degenerate); the
   configurations built outside the domain are flagged out_of_domain; the in-domain ones are not all
   flagged; status and prediction are the same at every scale, rotation and translation (float network:
   2e-5), and, for Gregory, whatever the lengths of the node normals (2e-5); invalid and degenerate rows
   say so.
4. The exported header, compiled with the C compiler (C99, -lm) and run on the same suite (raw[15], or
   raw[27] with the node normals nax nay naz .. ndx ndy ndz for Gregory), returns the same status (0 ok, 1
   invalid or degenerate, 2 out of domain) and the same prediction (to 1e-6).

Usage: network_extremes.py --gen-configs P --train-net P --evaluate-net P --cc CC --source-dir DIR --work DIR
                           [--surface bilinear|gregory]
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
NORMAL_COLUMNS = "nax,nay,naz,nbx,nby,nbz,ncx,ncy,ncz,ndx,ndy,ndz".split(",")
STATUS_CODE = {"ok": 0, "invalid": 1, "degenerate": 1, "out_of_domain": 2}
# Coarse-grid overrides of configs/gregory-paper.toml: ~830 labelled rows in well under a second.
GREGORY_GRID = ["--d_xy_points", "12", "--c_xy_points", "10", "--s_xy_points", "12", "--c_z_points", "3",
                "--s_z_points", "3", "--normal_sets", "3"]


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


def sub(p, q):
    return [p[k] - q[k] for k in range(3)]


def cross(p, q):
    return [p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]]


def unit(p):
    n = math.sqrt(sum(v * v for v in p))
    return [v / n for v in p]


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
            turn = (nx[0] - p[0]) * (pv[1] - p[1]) - (nx[1] - p[1]) * (pv[0] - p[0])
            ok = ok and turn > 0.05
        dist = [sum((s[k] - n[k]) ** 2 for k in range(3)) for n in nodes]
        if ok and dist[0] <= min(dist[1:]):
            return nodes + [s]


def corner_normal(nodes, i):
    """The segment's own unit normal at node i: (next - X) x (prev - X), normalised (SPEC 3, Eq 26)."""
    return unit(cross(sub(nodes[(i + 1) % 4], nodes[i]), sub(nodes[(i + 3) % 4], nodes[i])))


def tilted_normal(corner, tangent, phi):
    """corner tilted by an angle of the given tangent towards the azimuth phi (radians)."""
    t1 = unit(cross(corner, [1.0, 0.0, 0.0] if abs(corner[0]) < 0.9 else [0.0, 1.0, 0.0]))
    t2 = cross(corner, t1)
    return unit([corner[k] + tangent * (math.cos(phi) * t1[k] + math.sin(phi) * t2[k]) for k in range(3)])


def gregory_paper_configuration(rng):
    """A configuration of the Gregory study (paper Section 6) in the normalised frame: the bilinear study's
    setting with every interior angle in [60, 120] degrees and S passing the segment test at A, and node
    normals tilted from the segment's corner normals by an angle of tangent below 0.2, random azimuth."""
    while True:
        points = paper_configuration(rng)
        nodes, s = points[:4], points[4]
        angles = []
        for i in range(4):
            to_next, to_prev = sub(nodes[(i + 1) % 4], nodes[i]), sub(nodes[(i + 3) % 4], nodes[i])
            sine = math.sqrt(sum(v * v for v in cross(to_next, to_prev)))
            angles.append(math.degrees(math.atan2(sine, sum(to_next[k] * to_prev[k] for k in range(3)))))
        d = nodes[3]
        if min(angles) >= 60.0 and max(angles) <= 120.0 and s[1] >= 0.0 and s[0] * d[1] - s[1] * d[0] >= 0.0:
            break
    normals = [tilted_normal(corner_normal(nodes, i), 0.2 * rng.random(), 2 * math.pi * rng.random())
               for i in range(4)]
    return points, normals


def bilinear_suite(rng):
    """(name, expectation, points, None) with expectation 'in' (drawn from the paper's domain), 'out' (built
    outside it), 'any' (no expectation on the domain flag), 'invalid', 'degenerate'."""
    cases = [(f"paper_{k}", "in", paper_configuration(rng), None) for k in range(60)]
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    cases += [(name, expect, points, None) for name, expect, points in [
        ("slave_1e3_above", "out", square + [[0.2, 0.1, 1e3]]),
        ("slave_1e3_behind", "out", square + [[0.2, 0.1, -1e3]]),
        ("slave_1e3_sideways", "out", square + [[1e3, 0.5, 0.0]]),
        ("slave_behind_z_-1", "out", square + [[0.3, 0.2, -1.0]]),
        # Inside the declared domain (feature box of the grid cells, filters): predicted, not flagged.
        ("angle_179.9_at_A", "any", [[0, 0, 0], [1, 0, 0], [0, 1, 0.05],
                                     [math.cos(math.radians(179.9)), math.sin(math.radians(179.9)), 0], [0.1, 0.1, 0.1]]),
        ("aspect_1e3", "any", [[0, 0, 0], [1, 0, 0], [1, 1e-3, 0], [0, 1e-3, 0], [0.4, 5e-4, 0.1]]),
        # The mirror of SPEC 4 makes this a 1e3:1 segment in the canonical frame, like aspect_1e3 above.
        ("AD_1e3_longer", "any", [[0, 0, 0], [1, 0, 0], [1, 1e3, 0], [0, 1e3, 0], [0.3, 0.2, 0.1]]),
        ("C_far_out", "out", [[0, 0, 0], [1, 0, 0], [50, 40, 30], [0, 1, 0], [0.3, 0.2, 0.1]]),
        ("collapsed_A_B", "degenerate", [[0, 0, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0], [0.3, 0.2, 0.1]]),
        ("collinear", "degenerate", [[0, 0, 0], [1, 0, 0], [3, 0, 0], [2, 0, 0], [0.3, 0.2, 0.1]]),
    ]]
    for k, bad in enumerate(["nan", "inf", "-inf"]):
        points = [p[:] for p in square] + [[0.3, 0.2, 0.1]]
        points[k % 5][k % 3] = float(bad)
        cases.append((f"non_finite_{bad}", "invalid", points, None))
    return cases


def gregory_suite(rng):
    """(name, expectation, points, normals) as bilinear_suite, and 'out_filters' (outside the generator's filters,
    every feature inside the training range) and 'same:CASE' (status and prediction those of CASE at the same
    placement: the same configuration with node normals of other lengths)."""
    cases = []
    for k in range(60):
        points, normals = gregory_paper_configuration(rng)
        cases.append((f"paper_{k}", "in", points, normals))
    base_points, base_normals = cases[0][2], cases[0][3]
    for label, lengths in [("A_x1e-300", (1e-300, 1, 1, 1)), ("B_x1e300", (1, 1e300, 1, 1)),
                           ("C_x7.5", (1, 1, 7.5, 1)), ("all_x1e-300", (1e-300,) * 4), ("all_x1e300", (1e300,) * 4),
                           ("mixed", (1e-300, 1e300, 7.5, 0.02))]:
        normals = [[lengths[i] * v for v in base_normals[i]] for i in range(4)]
        cases.append((f"paper_0_normals_{label}", "same:paper_0", base_points, normals))
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    up = [[0.0, 0.0, 1.0]] * 4
    s = [0.3, 0.2, 0.1]

    def with_normal(i, n):
        normals = [v[:] for v in up]
        normals[i] = n
        return normals

    cases += [
        ("slave_1e3_above", "out", square + [[0.2, 0.1, 1e3]], up),
        ("slave_1e3_behind", "out", square + [[0.2, 0.1, -1e3]], up),
        ("slave_1e3_sideways", "out", square + [[1e3, 0.5, 0.0]], up),
        ("slave_behind_z_-1", "out", square + [[0.3, 0.2, -1.0]], up),
        ("AD_1e3_longer", "out", [[0, 0, 0], [1, 0, 0], [1, 1e3, 0], [0, 1e3, 0], s], up),
        ("C_far_out", "out", [[0, 0, 0], [1, 0, 0], [50, 40, 30], [0, 1, 0], s], up),
        ("normal_A_tilt_tan_1", "out", square + [s], with_normal(0, [1.0, 0.0, 1.0])),
        # Outside the generator's filters only (normal tilt, interior angle), every feature inside its range:
        # out_of_domain for evaluate-net and the C header alike.
        ("normal_C_tilt_tan_1", "out_filters", square + [s], with_normal(2, [0.0, -0.6, 0.6])),
        ("angle_130_at_A", "out_filters", [[0, 0, 0], [1, 0, 0], [1, 1, 0], [-0.3, 0.36, 0], [0.2, 0.1, 0.1]], up),
        ("normal_B_tan_1e6", "out", square + [s], with_normal(1, [1.0, 0.0, 1e-6])),
        ("collapsed_A_B", "degenerate", [[0, 0, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0], s], up),
        ("collinear", "degenerate", [[0, 0, 0], [1, 0, 0], [3, 0, 0], [2, 0, 0], s], up),
        ("normal_B_in_plane", "degenerate", square + [s], with_normal(1, [1.0, 0.0, 0.0])),
        ("normal_D_below_plane", "degenerate", square + [s], with_normal(3, [0.0, 1.0, -1e-6])),
        ("normal_C_flipped", "degenerate", square + [s], with_normal(2, [0.0, 0.0, -1.0])),
        ("normal_D_zero", "degenerate", square + [s], with_normal(3, [0.0, 0.0, 0.0])),
    ]
    for k, bad in enumerate(["nan", "inf", "-inf"]):
        points = [p[:] for p in square] + [s[:]]
        points[k % 5][k % 3] = float(bad)
        cases.append((f"non_finite_{bad}", "invalid", points, up))
        normals = [v[:] for v in up]
        normals[(k + 1) % 4][(k + 2) % 3] = float(bad)
        cases.append((f"non_finite_normal_{bad}", "invalid", [p[:] for p in square] + [s[:]], normals))
    return cases


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    for tool in ("gen-configs", "train-net", "evaluate-net"):
        parser.add_argument("--" + tool, required=True)
    parser.add_argument("--cc", default="cc")
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--surface", choices=("bilinear", "gregory"), default="bilinear")
    a = parser.parse_args()
    gregory = a.surface == "gregory"
    work = os.path.abspath(a.work)
    a.source_dir = os.path.abspath(a.source_dir)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    tools = {k: os.path.abspath(getattr(a, k.replace("-", "_"))) for k in ("gen-configs", "train-net", "evaluate-net")}
    failures = []

    # 1. A small trained network and its C header (train-net takes the surface from the dataset).
    if gregory:
        run([tools["gen-configs"], "--config", os.path.join(a.source_dir, "configs", "gregory-paper.toml"),
             *GREGORY_GRID, "--output", "data.h5", "--quiet"], work)
        run([tools["train-net"], "--data", "data.h5", "--output", "net.h5", "--epochs", "300", "--train_count", "400",
             "--seed", "1", "--export-header", "net.h", "--quiet"], work)
    else:
        run([tools["gen-configs"], "--config", os.path.join(a.source_dir, "configs", "tiny.toml"), "--output",
             "data.h5", "--quiet"], work)
        run([tools["train-net"], "--data", "data.h5", "--output", "net.h5", "--epochs", "200", "--train_count", "300",
             "--seed", "1", "--export-header", "net.h", "--quiet"], work)
    columns = COLUMNS + (NORMAL_COLUMNS if gregory else [])
    names = ("u", "v") if gregory else ("xi", "eta")

    # 2. The suite, at every scale, rotation and translation (node normals rotated only).
    rng = random.Random(2007)
    rows = []
    placements = [("unit", 1.0, None, 0.0)]
    for scale in (1e-6, 1e-3, 1e3, 1e6):
        placements.append((f"scale {scale:g}", scale, rotation(rng), 0.0))
        placements.append((f"scale {scale:g} translated 1e5", scale, rotation(rng), 1e5))
    identity = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    cases = gregory_suite(rng) if gregory else bilinear_suite(rng)
    for name, expect, points, normals in cases:
        for placement, scale, r, shift in placements:
            t = [shift * scale * v for v in (0.48, -0.6, 0.64)]
            world = transform(points, r or identity, scale, t)
            if normals is not None:
                world += transform(normals, r or identity, 1.0, [0.0, 0.0, 0.0])
            rows.append({"case": name, "expect": expect, "placement": placement,
                         "values": [v for p in world for v in p]})
    with open(os.path.join(work, "suite.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "expect", "placement"] + columns)
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
    by_placement = {}
    in_domain = 0
    for row, p in zip(rows, pred):
        where = f"{row['case']} at {row['placement']}"
        status = p["status"]
        xi, eta = p[names[0]], p[names[1]]
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
        if expect in ("out", "out_filters") and status != "out_of_domain":
            failures.append(f"{where}: built outside the training domain, evaluate-net says '{status}'")
        if expect in ("invalid", "degenerate") and status != expect:
            failures.append(f"{where}: expected {expect}, evaluate-net says '{status}'")
        if expect == "in" and status == "ok" and row["placement"] == "unit":
            in_domain += 1
        by_placement[(row["case"], row["placement"])] = (status, values)
        if expect.startswith("same:"):
            base = by_placement.get((expect[5:], row["placement"]))
            if base is None:
                failures.append(f"{where}: no prediction of {expect[5:]} to compare with")
            elif status != base[0]:
                failures.append(f"{where}: status '{status}', but '{base[0]}' for {expect[5:]} (other normal lengths)")
            elif values and base[1] and max(abs(values[0] - base[1][0]), abs(values[1] - base[1][1])) > 2e-5:
                failures.append(f"{where}: prediction {values} differs from {base[1]} for {expect[5:]} "
                                "(other normal lengths)")
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
    n_raw = len(columns)
    with open(harness, "w") as f:
        f.write('#include <stdio.h>\n#include <stdlib.h>\n#include "net.h"\n'
                f"int main(void) {{\n  double raw[{n_raw}], out[2];\n  char word[64];\n"
                f"  for (;;) {{\n    for (int i = 0; i < {n_raw}; ++i) {{\n"
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
        expected = STATUS_CODE.get(pr["status"], -1)  # the header tests the same domain, filters included
        if int(code) != expected:
            failures.append(f"{where}: returns {code} (expected {expected}), evaluate-net says '{pr['status']}'")
            continue
        if int(code) in (0, 2):
            if abs(float(x) - float(pr[names[0]])) > 1e-6 or abs(float(y) - float(pr[names[1]])) > 1e-6:
                failures.append(f"{where}: ({x}, {y}) vs evaluate-net ({pr[names[0]]}, {pr[names[1]]})")

    print(f"network extremes ({a.surface}): {len(rows)} predictions ({len(by_case)} cases x {len(placements)} "
          f"placements), {in_domain}/60 paper-domain cases inside the training domain, {len(failures)} failures")
    for message in failures[:40]:
        print("FAIL " + message)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
