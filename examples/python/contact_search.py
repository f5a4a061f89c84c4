#!/usr/bin/env python3
"""The contact search from Python on a mesh read with meshio (docs/python.md).

Two bodies of hexahedra, a flat plate and a block whose underside is curved, are written as a Gmsh file (each body
its physical group), read back with meshio, their surface faces found (the faces of one cell only, ordered so that
they face out of their cell), and the block's underside searched against the plate's top through ten increments as
the block is pressed down and slid along x. A table per increment; the gaps of the last drawn with matplotlib when
it is installed.

    PYTHONPATH=build/python python3 examples/python/contact_search.py [--output DIR]
"""

import argparse
import os
import sys

import meshio
import numpy as np

import contactnn

# The faces of a hexahedron (VTK's and Gmsh's node order, which is CalculiX's C3D8's), each a quad4.
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def block(nx, ny, nz, x0, x1, y0, y1, z0, z1, lift=None):
    """Points and hexahedra of a structured block; `lift(x, y)` raises its bottom layer (a curved underside)."""
    xs, ys, zs = np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1), np.linspace(z0, z1, nz + 1)
    points = np.array([[x, y, z] for z in zs for y in ys for x in xs])
    if lift is not None:
        bottom = points[:, 2] == z0
        points[bottom, 2] += lift(points[bottom, 0], points[bottom, 1])
    index = lambda i, j, k: (k * (ny + 1) + j) * (nx + 1) + i  # noqa: E731
    cells = [[index(i, j, k), index(i + 1, j, k), index(i + 1, j + 1, k), index(i, j + 1, k),
              index(i, j, k + 1), index(i + 1, j, k + 1), index(i + 1, j + 1, k + 1), index(i, j + 1, k + 1)]
             for k in range(nz) for j in range(ny) for i in range(nx)]
    return points, np.array(cells)


def write_mesh(path):
    """The two bodies as one Gmsh file, physical group 1 the plate, 2 the block."""
    plate_points, plate_cells = block(8, 8, 1, -1.0, 1.0, -1.0, 1.0, -0.25, 0.0)
    block_points, block_cells = block(6, 6, 2, -0.6, 0.6, -0.6, 0.6, 0.05, 0.5,
                                      lift=lambda x, y: 0.15 * (x * x + y * y))
    points = np.vstack([plate_points, block_points])
    cells = np.vstack([plate_cells, block_cells + len(plate_points)])
    body = np.concatenate([np.full(len(plate_cells), 1), np.full(len(block_cells), 2)])
    mesh = meshio.Mesh(points, [("hexahedron", cells)],
                       cell_data={"gmsh:physical": [body], "gmsh:geometrical": [body]})
    meshio.write(path, mesh, file_format="gmsh22", binary=False)


def surface_faces(points, cells):
    """The faces of `cells` (hexahedra) that belong to one cell only, each as its 4 point indices ordered
    counter-clockwise seen from outside ((B - A) x (D - A) points away from the cell)."""
    seen = {}
    for c, cell in enumerate(cells):
        for face in HEX_FACES:
            nodes = tuple(int(cell[k]) for k in face)
            key = tuple(sorted(nodes))
            seen[key] = None if key in seen else (c, nodes)
    faces = []
    for entry in seen.values():
        if entry is None:
            continue
        c, nodes = entry
        a, b, d = (points[n] for n in (nodes[0], nodes[1], nodes[3]))
        if np.dot(np.cross(b - a, d - a), a - points[cells[c]].mean(axis=0)) < 0:
            nodes = nodes[::-1]
        faces.append(nodes)
    return np.array(sorted(faces))


def outward_normal(points, face):
    a, b, c, d = (points[n] for n in face)
    n = np.cross(c - a, d - b)
    return n / np.linalg.norm(n)


def run(directory, increments=10, verbose=True):
    """Writes the mesh, reads it back, searches every increment; returns (slave point indices, each increment's
    coordinates and contacts)."""
    path = os.path.join(directory, "two-bodies.msh")
    write_mesh(path)
    mesh = meshio.read(path)
    points = np.ascontiguousarray(mesh.points, dtype=np.float64)
    cells = mesh.cells_dict["hexahedron"]
    body = mesh.cell_data_dict["gmsh:physical"]["hexahedron"]

    # The plate's top faces are the master surface, the nodes of the block's underside the slave nodes.
    plate = surface_faces(points, cells[body == 1])
    master = np.array([f for f in plate if outward_normal(points, f)[2] > 0.9])
    underside = [f for f in surface_faces(points, cells[body == 2]) if outward_normal(points, f)[2] < -0.5]
    slaves = np.unique(np.concatenate(underside))
    if verbose:
        print(f"{path}: {len(points)} points, {len(cells)} hexahedra; master {len(master)} quad4 faces, "
              f"{len(slaves)} slave nodes")

    search = contactnn.ContactSearch(["quad4"] * len(master), master.ravel(), len(points), slave_nodes=slaves,
                                     capture_distance=0.5)
    moving = np.zeros(len(points), bool)
    moving[np.unique(cells[body == 2])] = True
    history = []
    if verbose:
        print(f"{'increment':>9} {'found':>5} {'face':>4} {'edge':>4} {'vertex':>6} {'min gap':>10} {'max gap':>10}")
    for k in range(1, increments + 1):
        x = points.copy()
        x[moving] += [0.02 * k, 0.0, -0.012 * k]  # pressed down and slid along x
        contacts = search.update(x)
        history.append((x, contacts))
        found = contacts.status == 0
        where = np.bincount(contacts.location[found], minlength=3)
        if verbose:
            print(f"{k:>9} {found.sum():>5} {where[0]:>4} {where[1]:>4} {where[2]:>6} "
                  f"{contacts.gap[found].min():>10.5f} {contacts.gap[found].max():>10.5f}")
    return slaves, history


def plot(directory, slaves, history):
    """The last increment's gaps over the slave nodes' (x, y), if matplotlib is installed."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot")
        return
    x, contacts = history[-1]
    fig, ax = plt.subplots(figsize=(5, 4))
    s = ax.scatter(x[slaves, 0], x[slaves, 1], c=contacts.gap, cmap="viridis")
    fig.colorbar(s, ax=ax, label="gap")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(f"gaps at increment {len(history)}")
    out = os.path.join(directory, "gaps.png")
    fig.savefig(out, dpi=100)
    print(f"plot: {out}")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default=".", help="folder for two-bodies.msh and gaps.png")
    args = parser.parse_args(argv)
    os.makedirs(args.output, exist_ok=True)
    slaves, history = run(args.output)
    plot(args.output, slaves, history)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
