#!/usr/bin/env python3
"""A reference surface search in Python (SPEC 9) on a CalculiX history (SPEC 10), standing in for
`gen-configs --scene DECK --pair K --results RUN.frd --increment all` in the tests of scripts/calculix-compare.

It is slow and small on purpose: the deck subset of the project's example decks and CalculiX's own
metalforming deck (*NODE, *ELEMENT C3D8/C3D8R/C3D8I/C3D6 and the quadratic C3D20/C3D20R/C3D10/C3D15,
*NSET/*ELSET with GENERATE and set names, *SURFACE TYPE=NODE/ELEMENT, *CONTACT PAIR), flat faces (quad4 as
bilinear patches, tri3) and quadratic ones (quad8, tri6: their textbook shape functions, CalculiX's own face
tables), and only the columns calculix-compare reads: increment, slave, status, gap, location, px, py, pz,
face_type, nodes.
For each slave node, every master face whose box, grown by the capture distance, holds the node is a candidate;
on each, the closest point of the face (interior by Newton on the bilinear patch, else its edges and vertices;
a quadratic face: Newton from the minima of a sampled 9 x 9 grid, kept on the face, and each curved edge
sampled at 21 points and refined by 1-D Newton; a quadratic face's box holds its Bezier control points, which bound it);
the nearest wins (ties: lower element, then lower face). The gap is signed by the face normal, or by the
angle-weighted pseudo-normal at an edge or vertex (a curved face: its normal at its own nearest point of the
edge, its corner angle between its edges' tangents). The capture distance is the longest master edge (between
corners).

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
# Quadratic faces as CalculiX lists them (ifaceq, ifacet, ifacew2 in its gencontelem_n2f.f): outward, corners
# then the mid-side nodes of the edges corner 1-2, 2-3, ...
FACES["C3D20"] = {"S1": (4, 3, 2, 1, 11, 10, 9, 12), "S2": (5, 6, 7, 8, 13, 14, 15, 16),
                  "S3": (1, 2, 6, 5, 9, 18, 13, 17), "S4": (2, 3, 7, 6, 10, 19, 14, 18),
                  "S5": (3, 4, 8, 7, 11, 20, 15, 19), "S6": (4, 1, 5, 8, 12, 17, 16, 20)}
FACES["C3D10"] = {"S1": (1, 3, 2, 7, 6, 5), "S2": (1, 2, 4, 5, 9, 8), "S3": (2, 3, 4, 6, 10, 9),
                  "S4": (1, 4, 3, 8, 10, 7)}
FACES["C3D15"] = {"S1": (1, 3, 2, 9, 8, 7), "S2": (4, 5, 6, 10, 11, 12), "S3": (1, 2, 5, 4, 7, 14, 10, 13),
                  "S4": (2, 3, 6, 5, 8, 15, 11, 14), "S5": (3, 1, 4, 6, 9, 13, 12, 15)}
ALIASES = {"C3D8R": "C3D8", "C3D8I": "C3D8", "C3D20R": "C3D20"}
CORNERS = {"C3D8": 8, "C3D6": 6, "C3D20": 8, "C3D10": 4, "C3D15": 6}
NODE_COUNT = {"C3D8": 8, "C3D6": 6, "C3D20": 20, "C3D10": 10, "C3D15": 15}
FACE_TYPE = {4: "quad4", 3: "tri3", 8: "quad8", 6: "tri6"}


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
            count = NODE_COUNT.get(etype)
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
    faces = [(eid, label, f, enodes[:CORNERS[elements[eid][0]]]) for eid, label, f, enodes in faces]
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


# ---------------------------------------------------------------------------------------------------------
# Quadratic faces (quad8: (xi, eta) in [-1, 1]^2; tri6: (r, s), r, s >= 0, r + s <= 1), by the textbook shape
# functions (Zienkiewicz & Taylor, vol. 1, 6.4 and 6.6) and their derivatives.
def shape_quadratic(n, a, b):
    """Shape functions and their a- and b-derivatives of the 8- or 6-node face at (a, b)."""
    if n == 8:
        s_, t_ = (-1, 1, 1, -1), (-1, -1, 1, 1)
        w, wa, wb = [], [], []
        for i in range(4):
            s, t = s_[i], t_[i]
            w.append(0.25 * (1 + s * a) * (1 + t * b) * (s * a + t * b - 1))
            wa.append(0.25 * s * (1 + t * b) * (2 * s * a + t * b))
            wb.append(0.25 * t * (1 + s * a) * (s * a + 2 * t * b))
        w += [0.5 * (1 - a * a) * (1 - b), 0.5 * (1 + a) * (1 - b * b), 0.5 * (1 - a * a) * (1 + b),
              0.5 * (1 - a) * (1 - b * b)]
        wa += [-a * (1 - b), 0.5 * (1 - b * b), -a * (1 + b), -0.5 * (1 - b * b)]
        wb += [-0.5 * (1 - a * a), -b * (1 + a), 0.5 * (1 - a * a), -b * (1 - a)]
        return w, wa, wb
    l0 = 1 - a - b
    w = [l0 * (2 * l0 - 1), a * (2 * a - 1), b * (2 * b - 1), 4 * l0 * a, 4 * a * b, 4 * b * l0]
    wa = [-(4 * l0 - 1), 4 * a - 1, 0.0, 4 * (l0 - a), 4 * b, -4 * b]
    wb = [-(4 * l0 - 1), 0.0, 4 * b - 1, -4 * a, 4 * a, 4 * (l0 - b)]
    return w, wa, wb


def quadratic_point(x, a, b):
    """P, P_a, P_b of the quadratic face with nodes x at (a, b)."""
    w, wa, wb = shape_quadratic(len(x), a, b)
    p, pa, pb = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    for k, node in enumerate(x):
        for i in range(3):
            p[i] += w[k] * node[i]
            pa[i] += wa[k] * node[i]
            pb[i] += wb[k] * node[i]
    return tuple(p), tuple(pa), tuple(pb)


def inside_quadratic(n, a, b, margin=0.0):
    if n == 8:
        return -1 - margin <= a <= 1 + margin and -1 - margin <= b <= 1 + margin
    return a >= -margin and b >= -margin and a + b <= 1 + margin


def onto_quadratic(n, a, b):
    """(a, b) moved onto the closed face in the parameter plane."""
    if n == 8:
        return min(1.0, max(-1.0, a)), min(1.0, max(-1.0, b))
    if a + b > 1:
        shift = 0.5 * (a + b - 1)
        a, b = a - shift, b - shift
    a, b = min(1.0, max(0.0, a)), min(1.0, max(0.0, b))
    if a + b > 1:
        a, b = (a, 1 - a) if a >= b else (1 - b, b)
    return a, b


def quadratic_edge(n, e, t):
    """Face parameters of the point t in [0, 1] of edge e (t = 0 its first corner, 1 its second)."""
    if n == 8:
        return ((-1 + 2 * t, -1.0), (1.0, -1 + 2 * t), (1 - 2 * t, 1.0), (-1.0, 1 - 2 * t))[e]
    return ((t, 0.0), (1 - t, t), (0.0, 1 - t))[e]


def closest_on_quadratic(s, x):
    """(distance, point, location, key, normal at the point, (a, b)) of the quad8 / tri6 with nodes x."""
    n = len(x)
    k = n // 2
    def f(a, b):
        r = sub(s, quadratic_point(x, a, b)[0])
        return dot(r, r)
    candidates = []
    # Interior: Newton on the gradient of |S - P|^2 / 2 from every minimum of a sampled grid, kept on the face.
    m = 8
    lo, width = (-1.0, 2.0) if n == 8 else (0.0, 1.0)
    grid = {}
    for i in range(m + 1):
        for j in range(m + 1):
            a, b = lo + width * i / m, lo + width * j / m
            if inside_quadratic(n, a, b, 1e-12):
                grid[(i, j)] = f(a, b)
    h = 1e-5
    for (i, j), value in grid.items():
        if any(grid.get((i + di, j + dj), float("inf")) < value for di in (-1, 0, 1) for dj in (-1, 0, 1)):
            continue
        a, b = lo + width * i / m, lo + width * j / m
        converged = False
        for _ in range(60):
            p, pa, pb = quadratic_point(x, a, b)
            r = sub(p, s)
            g = (dot(pa, r), dot(pb, r))
            # Hessian of |S - P|^2 / 2 by central differences of the gradient.
            def grad(u, v):
                q, qa, qb = quadratic_point(x, u, v)
                rr = sub(q, s)
                return dot(qa, rr), dot(qb, rr)
            ga, gA, gb, gB = grad(a + h, b), grad(a - h, b), grad(a, b + h), grad(a, b - h)
            h00, h11 = (ga[0] - gA[0]) / (2 * h), (gb[1] - gB[1]) / (2 * h)
            h01 = 0.25 * ((ga[1] - gA[1]) + (gb[0] - gB[0])) / h
            det = h00 * h11 - h01 * h01
            if not (h00 > 0 and det > 0):
                break
            da, db = (h11 * g[0] - h01 * g[1]) / det, (h00 * g[1] - h01 * g[0]) / det
            na, nb = onto_quadratic(n, a - da, b - db)
            moved = max(abs(na - a), abs(nb - b))
            a, b = na, nb
            if max(abs(da), abs(db)) < 1e-12:  # at rounding level (the Hessian's differences carry ~1e-10)
                converged = True
                break
            if moved < 1e-15:
                break
        if converged:
            p, pa, pb = quadratic_point(x, a, b)
            candidates.append((norm(sub(s, p)), p, "face", None, unit(cross(pa, pb)), (a, b)))
    # Edges: 21 samples, each sampled minimum refined by 1-D Newton (the second derivative by differences).
    for e in range(k):
        end0, end1 = quadratic_edge(n, e, 0.0), quadratic_edge(n, e, 1.0)
        da, db = end1[0] - end0[0], end1[1] - end0[1]

        def curve(t):
            a, b = quadratic_edge(n, e, t)
            p, pa, pb = quadratic_point(x, a, b)
            return p, tuple(pa[i] * da + pb[i] * db for i in range(3))

        ts = [i / 20 for i in range(21)]
        fs = []
        for t in ts:
            r = sub(s, curve(t)[0])
            fs.append(dot(r, r))
        for i, t in enumerate(ts):
            if (i > 0 and fs[i - 1] < fs[i]) or (i < 20 and fs[i + 1] < fs[i]):
                continue
            for _ in range(60):
                p, pt = curve(t)
                g = dot(pt, sub(p, s))
                p1, pt1 = curve(t + h)
                p0, pt0 = curve(t - h)
                slope = (dot(pt1, sub(p1, s)) - dot(pt0, sub(p0, s))) / (2 * h)
                if not slope > 0:
                    break
                nt = min(1.0, max(0.0, t - g / slope))
                done = abs(nt - t) < 1e-14
                t = nt
                if done:
                    break
            a, b = quadratic_edge(n, e, t)
            p = quadratic_point(x, a, b)[0]
            if t <= 0.0 or t >= 1.0:
                key = ("vertex", e if t <= 0.0 else (e + 1) % k)
            else:
                key = ("edge", e)
            candidates.append((norm(sub(s, p)), p, key[0], key, None, (a, b)))
    return min(candidates, key=lambda c: c[0])


def quadratic_normal_on_edge(x, e, point):
    """The unit normal of quadratic face x at its point of edge e nearest `point`."""
    n = len(x)
    best = None
    for i in range(201):
        a, b = quadratic_edge(n, e, i / 200)
        d = norm(sub(point, quadratic_point(x, a, b)[0]))
        if best is None or d < best[0]:
            best = (d, a, b)
    _, pa, pb = quadratic_point(x, best[1], best[2])
    return unit(cross(pa, pb))


def quadratic_corner_term(x, c):
    """Corner angle times unit normal of quadratic face x at its corner c (a vertex pseudo-normal's term)."""
    n = len(x)
    k = n // 2
    a, b = quadratic_edge(n, c, 0.0)
    _, pa, pb = quadratic_point(x, a, b)

    def tangent(e, forward):  # d/dt of edge e at its end, pointing into the edge
        a0, b0 = quadratic_edge(n, e, 0.0)
        a1, b1 = quadratic_edge(n, e, 1.0)
        d = (a1 - a0, b1 - b0) if forward else (a0 - a1, b0 - b1)
        return tuple(pa[i] * d[0] + pb[i] * d[1] for i in range(3))

    t1, t2 = tangent(c, True), tangent((c - 1) % k, False)
    angle = math.acos(max(-1.0, min(1.0, dot(unit(t1), unit(t2)))))
    return scale(angle, unit(cross(pa, pb)))


def search(slaves, faces, position):
    """SPEC 9 on the geometry position(node id): one result per slave node, None where no face is near."""
    xs = [[position(n) for n in f] for _, _, f, _ in faces]
    centroids = [scale(1.0 / len(enodes), [sum(position(n)[i] for n in enodes) for i in range(3)])
                 for _, _, _, enodes in faces]
    # Orient each face outward (its normal away from its element's centroid).
    for k, x in enumerate(xs):
        corners = x[:len(x) // 2] if len(x) in (6, 8) else x
        c = scale(1.0 / len(corners), [sum(p[i] for p in corners) for i in range(3)])
        n = cross(sub(corners[1], corners[0]), sub(corners[-1], corners[0]))
        if dot(n, sub(c, centroids[k])) < 0:
            if len(x) in (6, 8):  # corners reversed from the first; each mid-side node stays with its edge
                h = len(x) // 2
                order = [0] + list(range(h - 1, 0, -1)) + [h + (h - 1)] + [h + i for i in range(h - 2, -1, -1)]
            else:
                order = list(range(len(x)))[::-1]
            xs[k] = [x[i] for i in order]
            faces[k] = (faces[k][0], faces[k][1], [faces[k][2][i] for i in order], faces[k][3])
    corner_lists = [x[:len(x) // 2] if len(x) in (6, 8) else x for x in xs]
    capture = max(norm(sub(x[k], x[(k + 1) % len(x)])) for x in corner_lists for k in range(len(x)))

    def hull(x):
        """Points whose box holds the face: its nodes, and a quadratic face's Bezier control points."""
        if len(x) == 6:
            return x + [sub(scale(2, x[3 + e]), scale(0.5, add(x[e], x[(e + 1) % 3]))) for e in range(3)]
        if len(x) == 8:
            mid = lambda f0, fm, f1: sub(scale(2, fm), scale(0.5, add(f0, f1)))
            centre = quadratic_point(x, 0.0, 0.0)[0]
            rows = [(x[0], mid(x[0], x[4], x[1]), x[1]), (x[7], mid(x[7], centre, x[5]), x[5]),
                    (x[3], mid(x[3], x[6], x[2]), x[2])]
            return [rows[j][i] if j != 1 else mid(rows[0][i], rows[1][i], rows[2][i]) for i in range(3)
                    for j in range(3)] + list(rows[0]) + list(rows[2])
        return x

    boxes = [([min(p[i] for p in hull(x)) - capture for i in range(3)],
              [max(p[i] for p in hull(x)) + capture for i in range(3)]) for x in xs]
    normals = [unit(cross(sub(x[2], x[0]), sub(x[3] if len(x) == 4 else x[1], x[1])) if len(x) == 4
                    else cross(sub(x[1], x[0]), sub(x[2], x[0]))) for x in corner_lists]
    # Pseudo-normals of flat faces: edges by the sum of their faces' normals, vertices angle-weighted (a curved
    # face's terms are computed where a point needs them).
    edge_normal, vertex_normal = {}, {}
    edge_faces, vertex_faces = {}, {}
    for k, (_, _, f, _) in enumerate(faces):
        x = corner_lists[k]
        f = f[:len(x)]
        for i in range(len(f)):
            edge_faces.setdefault(tuple(sorted((f[i], f[(i + 1) % len(f)]))), []).append((k, i))
            vertex_faces.setdefault(f[i], []).append((k, i))
        if len(xs[k]) in (6, 8):
            continue
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
        # Nearest box first; a face whose box (without the capture margin) is farther than the best point so far
        # cannot hold a nearer one.
        near = []
        for k, (lo, hi) in enumerate(boxes):
            if not all(lo[i] <= s[i] <= hi[i] for i in range(3)):
                continue
            gap = [max(lo[i] + capture - s[i], 0.0, s[i] - hi[i] + capture) for i in range(3)]
            near.append((norm(gap), k))
        for bound, k in sorted(near):
            if best is not None and bound > best[0]:
                break
            if len(xs[k]) in (6, 8):
                d, p, location, key, n, _ = closest_on_quadratic(s, xs[k])
            else:
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
        corners = f[:len(corner_lists[k])]
        curved = any(len(xs[j]) in (6, 8) for j in range(len(xs)))
        if location == "face":
            direction = n
        elif location == "edge" and not curved:
            direction = edge_normal[tuple(sorted((f[key[1]], f[(key[1] + 1) % len(f)])))]
        elif location == "edge":
            direction = (0.0, 0.0, 0.0)
            for j, e in edge_faces[tuple(sorted((corners[key[1]], corners[(key[1] + 1) % len(corners)])))]:
                term = quadratic_normal_on_edge(xs[j], e, p) if len(xs[j]) in (6, 8) else normals[j]
                direction = add(direction, term)
        elif not curved:
            direction = vertex_normal[f[key[1]]]
        else:
            direction = (0.0, 0.0, 0.0)
            for j, c in vertex_faces[corners[key[1]]]:
                if len(xs[j]) in (6, 8):
                    term = quadratic_corner_term(xs[j], c)
                else:
                    x = corner_lists[j]
                    prev, nxt = x[c - 1], x[(c + 1) % len(x)]
                    angle = math.acos(max(-1.0, min(1.0, dot(unit(sub(prev, x[c])), unit(sub(nxt, x[c]))))))
                    term = scale(angle, normals[j])
                direction = add(direction, term)
        sign = -1.0 if dot(sub(s, p), direction) < 0 else 1.0
        results[sid] = (sign * d, p, location, FACE_TYPE[len(f)], f)
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
