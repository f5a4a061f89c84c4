#!/usr/bin/env python3
"""A reference surface search in Python (SPEC 9) on a CalculiX history (SPEC 10), standing in for
`gen-configs --scene DECK --pair K --results RUN.frd --increment all` in the tests of scripts/calculix-compare.

It is slow and small on purpose: the deck subset of the project's example decks and CalculiX's own
metalforming deck (*NODE, *ELEMENT C3D8/C3D8R/C3D8I/C3D6, *NSET/*ELSET with GENERATE and set names,
*SURFACE TYPE=NODE/ELEMENT, *CONTACT PAIR), flat faces (quad4 as bilinear patches, tri3), and only the
columns calculix-compare reads: increment, slave, status, gap, location, px, py, pz, face_type, nodes.
For each slave node, every master face whose box, grown by the capture distance, holds the node is a candidate;
on each, the closest point of the face (interior by Newton on the bilinear patch, else its edges and vertices);
the nearest wins (ties: lower element, then lower face). The gap is signed by the face normal, or by the
angle-weighted pseudo-normal at an edge or vertex. The capture distance is the longest master edge.

--perturb makes it wrong on purpose, for the tests that calculix-compare fails when it should:
  drop     the deepest slave node of every increment (the smallest gap) gets status no_segment;
  offset   every gap is moved by 1e-3;
  nodes    no `nodes` column (calculix-compare then bounds the face by all nodes of the file).

Usage: surface_search_reference.py --scene DECK --pair K --results RUN.frd --increment all --output OUT.csv
                                   [--surface bilinear] [--perturb drop|offset|nodes]
"""
import argparse
import csv
import importlib.machinery
import importlib.util
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def load_compare():
    """scripts/calculix-compare as a module (its .frd reader)."""
    path = os.path.join(HERE, "..", "..", "scripts", "calculix-compare")
    loader = importlib.machinery.SourceFileLoader("calculix_compare", path)
    spec = importlib.util.spec_from_loader("calculix_compare", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


# Face node orders, 1-based, CalculiX numbering (SPEC 7 and 9).
FACES = {
    "C3D8": {"S1": (1, 2, 3, 4), "S2": (5, 8, 7, 6), "S3": (1, 5, 6, 2), "S4": (2, 6, 7, 3), "S5": (3, 7, 8, 4),
             "S6": (4, 8, 5, 1)},
    "C3D6": {"S1": (1, 2, 3), "S2": (4, 6, 5), "S3": (1, 4, 5, 2), "S4": (2, 5, 6, 3), "S5": (3, 6, 4, 1)},
}
ALIASES = {"C3D8R": "C3D8", "C3D8I": "C3D8"}


# ---------------------------------------------------------------------------------------------------------
# Vectors.
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(s, a):
    return (s * a[0], s * a[1], s * a[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    n = norm(a)
    return scale(1.0 / n, a) if n > 0 else a


# ---------------------------------------------------------------------------------------------------------
# The deck.
def keyword_params(line):
    parts = [p.strip() for p in line.split(",")]
    params = {}
    for p in parts[1:]:
        if "=" in p:
            k, v = p.split("=", 1)
            params[k.strip().upper()] = v.strip()
        elif p:
            params[p.upper()] = ""
    return parts[0].upper(), params


def read_deck(path):
    nodes, elements, nsets, elsets, surfaces, pairs = {}, {}, {}, {}, {}, []
    with open(path, errors="replace") as f:
        lines = [l.rstrip("\r\n") for l in f]
    keyword, params, pending = None, {}, []
    for line in lines:
        s = line.strip()
        if not s or s.startswith("**"):
            continue
        if s.startswith("*"):
            keyword, params = keyword_params(s)
            pending = []
            if keyword == "*NODE" and "NSET" in params:
                nsets.setdefault(params["NSET"].upper(), [])
            continue
        fields = [t.strip() for t in s.split(",")]
        if keyword == "*NODE":
            nid = int(fields[0])
            nodes[nid] = tuple(float(t) for t in fields[1:4])
            if "NSET" in params:
                nsets[params["NSET"].upper()].append(nid)
        elif keyword == "*ELEMENT":
            pending += [t for t in fields if t]
            etype = ALIASES.get(params["TYPE"].upper(), params["TYPE"].upper())
            count = {"C3D8": 8, "C3D6": 6}.get(etype)
            if count is None:
                raise SystemExit("%s: element type %s is not supported by this reference" % (path, etype))
            if len(pending) >= count + 1:
                eid = int(pending[0])
                elements[eid] = (etype, [int(t) for t in pending[1:count + 1]])
                if "ELSET" in params:
                    elsets.setdefault(params["ELSET"].upper(), []).append(eid)
                pending = []
        elif keyword in ("*NSET", "*ELSET"):
            name = params["NSET" if keyword == "*NSET" else "ELSET"].upper()
            target, sets = (nsets, nsets) if keyword == "*NSET" else (elsets, elsets)
            members = target.setdefault(name, [])
            tokens = [t for t in fields if t]
            if "GENERATE" in params:
                a, b = int(tokens[0]), int(tokens[1])
                step = int(tokens[2]) if len(tokens) > 2 else 1
                members += list(range(a, b + 1, step))
            else:
                for t in tokens:
                    members += [int(t)] if t.lstrip("-").isdigit() else sets[t.upper()]
        elif keyword == "*SURFACE":
            name = params["NAME"].upper()
            kind = params.get("TYPE", "ELEMENT").upper()
            surface = surfaces.setdefault((name, kind), [])
            if kind == "NODE":
                t = fields[0]
                surface += [int(t)] if t.isdigit() else nsets[t.upper()]
            else:
                t, label = fields[0], fields[1].upper()
                for eid in ([int(t)] if t.isdigit() else elsets[t.upper()]):
                    surface.append((eid, label))
        elif keyword == "*CONTACT PAIR":
            pairs.append((fields[0].upper(), fields[1].upper(), params.get("TYPE", "").upper()))
    return nodes, elements, surfaces, pairs


def pair_geometry(deck_path, pair):
    nodes, elements, surfaces, pairs = read_deck(deck_path)
    slave_name, master_name, pair_type = pairs[pair]
    faces = []  # (element id, face label, node ids oriented outward)
    for eid, label in surfaces[(master_name, "ELEMENT")]:
        etype, enodes = elements[eid]
        order = FACES[etype][label]
        faces.append((eid, label, [enodes[k - 1] for k in order], enodes))
    master_nodes = {n for _, _, f, _ in faces for n in f}
    if (slave_name, "NODE") in surfaces and (pair_type == "NODE TO SURFACE" or (slave_name, "ELEMENT")
                                               not in surfaces):
        slaves = set(surfaces[(slave_name, "NODE")])
    else:
        slaves = set()
        for eid, label in surfaces[(slave_name, "ELEMENT")]:
            etype, enodes = elements[eid]
            slaves |= {enodes[k - 1] for k in FACES[etype][label]}
    return sorted(slaves - master_nodes), faces


# ---------------------------------------------------------------------------------------------------------
# Closest points.
def closest_on_segment(s, a, b):
    ab = sub(b, a)
    t = dot(sub(s, a), ab) / dot(ab, ab)
    if t <= 0:
        return a, ("vertex", 0)
    if t >= 1:
        return b, ("vertex", 1)
    return add(a, scale(t, ab)), ("edge", 0)


def closest_on_triangle(s, a, b, c):
    n = cross(sub(b, a), sub(c, a))
    p = sub(s, scale(dot(sub(s, a), n) / dot(n, n), n))
    # Barycentric inside test of the plane projection.
    inside = all(dot(cross(sub(q, p0), sub(p, p0)), n) >= 0 for p0, q in ((a, b), (b, c), (c, a)))
    if inside:
        return p, ("face", None)
    return None, None


def bilinear(x, xi, eta):
    a, b, c, d = x
    w = ((1 - xi) * (1 - eta) / 4, (1 + xi) * (1 - eta) / 4, (1 + xi) * (1 + eta) / 4, (1 - xi) * (1 + eta) / 4)
    dxi = (-(1 - eta) / 4, (1 - eta) / 4, (1 + eta) / 4, -(1 + eta) / 4)
    deta = (-(1 - xi) / 4, -(1 + xi) / 4, (1 + xi) / 4, (1 - xi) / 4)
    p = tuple(sum(w[k] * x[k][i] for k in range(4)) for i in range(3))
    pxi = tuple(sum(dxi[k] * x[k][i] for k in range(4)) for i in range(3))
    peta = tuple(sum(deta[k] * x[k][i] for k in range(4)) for i in range(3))
    pxe = tuple((a[i] - b[i] + c[i] - d[i]) / 4 for i in range(3))
    return p, pxi, peta, pxe


def closest_on_quad_interior(s, x):
    """Newton on Eqs 7-8 (exact Jacobian) from the centre; the point if it converges inside."""
    xi = eta = 0.0
    for _ in range(30):
        p, pxi, peta, pxe = bilinear(x, xi, eta)
        r = sub(s, p)
        f1, f2 = dot(pxi, r), dot(peta, r)
        j11, j22 = -dot(pxi, pxi), -dot(peta, peta)
        j12 = -dot(pxi, peta) + dot(pxe, r)
        det = j11 * j22 - j12 * j12
        if det == 0:
            return None, None
        dxi, deta = (j22 * f1 - j12 * f2) / det, (j11 * f2 - j12 * f1) / det
        xi, eta = xi - dxi, eta - deta
        if abs(dxi) + abs(deta) < 1e-14:
            break
    if abs(xi) <= 1 and abs(eta) <= 1:
        p, pxi, peta, _ = bilinear(x, xi, eta)
        return p, unit(cross(pxi, peta))
    return None, None


def closest_on_face(s, x):
    """(distance, point, location, key, face normal at the point or None); key names the edge/vertex."""
    best = None
    if len(x) == 4:
        p, n = closest_on_quad_interior(s, x)
    else:
        p, _ = closest_on_triangle(s, *x)
        n = unit(cross(sub(x[1], x[0]), sub(x[2], x[0]))) if p is not None else None
    if p is not None:
        best = (norm(sub(s, p)), p, "face", None, n)
    for k in range(len(x)):
        a, b = x[k], x[(k + 1) % len(x)]
        q, (where, end) = closest_on_segment(s, a, b)
        d = norm(sub(s, q))
        if best is None or d < best[0]:
            key = ("vertex", (k + end) % len(x)) if where == "vertex" else ("edge", k)
            best = (d, q, key[0], key, None)
    return best


def search(slaves, faces, position):
    """SPEC 9 on the geometry position(node id): one result per slave node, None where no face is near."""
    xs = [[position(n) for n in f] for _, _, f, _ in faces]
    centroids = [scale(1.0 / len(enodes), [sum(position(n)[i] for n in enodes) for i in range(3)])
                 for _, _, _, enodes in faces]
    # Orient each face outward (its normal away from its element's centroid).
    for k, x in enumerate(xs):
        c = scale(1.0 / len(x), [sum(p[i] for p in x) for i in range(3)])
        n = cross(sub(x[1], x[0]), sub(x[-1], x[0]))
        if dot(n, sub(c, centroids[k])) < 0:
            xs[k] = x[::-1]
            faces[k] = (faces[k][0], faces[k][1], faces[k][2][::-1], faces[k][3])
    capture = max(norm(sub(x[k], x[(k + 1) % len(x)])) for x in xs for k in range(len(x)))
    boxes = [([min(p[i] for p in x) - capture for i in range(3)], [max(p[i] for p in x) + capture for i in range(3)])
             for x in xs]
    normals = [unit(cross(sub(x[2], x[0]), sub(x[3] if len(x) == 4 else x[1], x[1])) if len(x) == 4
                    else cross(sub(x[1], x[0]), sub(x[2], x[0]))) for x in xs]
    # Pseudo-normals: edges by the sum of their faces' normals, vertices angle-weighted.
    edge_normal, vertex_normal = {}, {}
    for k, (_, _, f, _) in enumerate(faces):
        x = xs[k]
        for i in range(len(f)):
            e = tuple(sorted((f[i], f[(i + 1) % len(f)])))
            edge_normal[e] = add(edge_normal.get(e, (0, 0, 0)), normals[k])
            prev, nxt = x[i - 1], x[(i + 1) % len(x)]
            angle = math.acos(max(-1.0, min(1.0, dot(unit(sub(prev, x[i])), unit(sub(nxt, x[i]))))))
            vertex_normal[f[i]] = add(vertex_normal.get(f[i], (0, 0, 0)), scale(angle, normals[k]))
    results = {}
    for sid in slaves:
        s = position(sid)
        best = None
        for k, (lo, hi) in enumerate(boxes):
            if not all(lo[i] <= s[i] <= hi[i] for i in range(3)):
                continue
            d, p, location, key, n = closest_on_face(s, xs[k])
            if d > capture:
                continue
            candidate = (d, faces[k][0], faces[k][1], k, p, location, key, n)
            if best is None or candidate[:3] < best[:3]:
                best = candidate
        if best is None:
            results[sid] = None
            continue
        d, _, _, k, p, location, key, n = best
        f = faces[k][2]
        if location == "face":
            direction = n
        elif location == "edge":
            direction = edge_normal[tuple(sorted((f[key[1]], f[(key[1] + 1) % len(f)])))]
        else:
            direction = vertex_normal[f[key[1]]]
        sign = -1.0 if dot(sub(s, p), direction) < 0 else 1.0
        results[sid] = (sign * d, p, location, "quad4" if len(f) == 4 else "tri3", f)
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--pair", type=int, default=0)
    parser.add_argument("--surface", default="bilinear", choices=["bilinear"])
    parser.add_argument("--results", required=True)
    parser.add_argument("--increment", required=True, choices=["all"])
    parser.add_argument("--output", required=True)
    parser.add_argument("--perturb", choices=["drop", "offset", "nodes"])
    args = parser.parse_args()
    frd = load_compare().Frd(args.results)
    slaves, faces = pair_geometry(args.scene, args.pair)
    header = ["increment", "slave", "status", "gap", "location", "px", "py", "pz", "face_type"]
    if args.perturb != "nodes":
        header.append("nodes")
    with open(args.output, "w", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(header)
        for index, inc in enumerate(frd.increments, start=1):
            disp = inc["disp"]

            def position(n):
                x = frd.nodes[n][0]
                u = disp[n][0] if n in disp else (0.0, 0.0, 0.0)
                return (x[0] + u[0], x[1] + u[1], x[2] + u[2])

            results = search(slaves, list(faces), position)
            found = [(r[0], sid) for sid, r in results.items() if r is not None]
            deepest = min(found)[1] if found else None
            for sid in slaves:
                r = results[sid]
                if r is None or (args.perturb == "drop" and sid == deepest):
                    row = [index, sid, "no_segment"] + [""] * (len(header) - 3)
                else:
                    gap, p, location, face_type, nodes = r
                    gap += 1e-3 if args.perturb == "offset" else 0.0
                    row = [index, sid, "ok", repr(gap), location] + [repr(c) for c in p] + [face_type]
                    if args.perturb != "nodes":
                        row.append(" ".join(str(n) for n in nodes))
                out.writerow(row)
    return 0


if __name__ == "__main__":
    sys.exit(main())
