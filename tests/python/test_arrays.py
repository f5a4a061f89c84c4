"""The module's arrays: LocalSearch and FaceSearch against evaluate-net to the last bit, float64 and float32, out=,
inputs read where they lie (no copy), and every bad input refused with a message that says what was expected."""

import csv
import os

import numpy as np
import pytest

import contactnn
from conftest import read_csv, run_tool

RAW = ["ax", "ay", "az", "bx", "by", "bz", "cx", "cy", "cz", "dx", "dy", "dz", "sx", "sy", "sz"]
NORMALS = ["nax", "nay", "naz", "nbx", "nby", "nbz", "ncx", "ncy", "ncz", "ndx", "ndy", "ndz"]


def raw_rows(path, gregory):
    rows = read_csv(path)
    # (An empty field is a missing value: the example files hold such rows on purpose; evaluate-net reads them as NaN.)
    return np.array([[float(r[k] or "nan") for k in RAW + (NORMALS if gregory else [])] for r in rows])


@pytest.mark.parametrize("surface,weights", [("bilinear", "bilinear-8.h5"), ("gregory", "gregory-32.h5")])
@pytest.mark.parametrize("steps", [0, 2])
def test_local_search_is_evaluate_net(surface, weights, steps, source_dir, evaluate_net, tmp_path):
    data = os.path.join(source_dir, "data", "examples", f"raw-{surface}.csv")
    network_path = os.path.join(source_dir, "data", "weights", weights)
    out = tmp_path / "pred.csv"
    run_tool([evaluate_net, "--weights", network_path, "--input", data, "--output", str(out),
              "--newton-steps", str(steps)])
    expected = read_csv(out)
    method = "network" if steps == 0 else f"network+newton:{steps}"
    search = contactnn.LocalSearch(surface, method, network=contactnn.read_network(network_path))
    param, gap, status = search.run(raw_rows(data, surface == "gregory"))
    columns = ("xi", "eta") if surface == "bilinear" else ("u", "v")
    assert len(expected) == len(param) > 0
    for i, row in enumerate(expected):
        assert contactnn.STATUS_NAMES[status[i]] == row["status"], i
        if row[columns[0]] == "":
            continue  # (evaluate-net writes no coordinates for a degenerate or invalid row)
        assert param[i].tolist() == [float(row[columns[0]]), float(row[columns[1]])], i


def unit_square_queries(n, seed=1):
    """n slave points over the unit square in the xy-plane (A, B, C, D counter-clockwise): the answer is (2x - 1,
    2y - 1) and the gap z."""
    rng = np.random.default_rng(seed)
    s = np.column_stack([rng.uniform(0.05, 0.95, n), rng.uniform(0.05, 0.95, n), rng.uniform(-0.2, 0.2, n)])
    square = np.array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], float)
    return np.column_stack([np.tile(square, (n, 1)), s]), s


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_both_dtypes_and_out(dtype):
    raw, s = unit_square_queries(100)
    raw = np.ascontiguousarray(raw, dtype=dtype)
    search = contactnn.LocalSearch("bilinear", "newton")
    param, gap, status = search.run(raw)
    assert param.dtype == dtype and gap.dtype == dtype and status.dtype == np.uint8
    assert param.shape == (100, 2) and gap.shape == (100,) and status.shape == (100,)
    tol = 1e-12 if dtype == np.float64 else 1e-6
    assert np.all(status == contactnn.STATUS_NAMES.index("ok"))
    np.testing.assert_allclose(param, 2 * s[:, :2] - 1, atol=tol)
    np.testing.assert_allclose(gap, s[:, 2], atol=tol)
    # The same answers written into the caller's arrays, which are returned.
    out = (np.full((100, 2), np.nan, dtype), np.full(100, np.nan, dtype), np.full(100, 9, np.uint8))
    got = search.run(raw, out=out)
    for given, returned, fresh in zip(out, got, (param, gap, status)):
        assert np.shares_memory(given, returned)
        assert np.array_equal(given, fresh)
    # A query's bits do not depend on its batch (lib/search's promise, through the module).
    one = search.run(raw[7:8].copy())
    assert one[0].tolist() == param[7:8].tolist()


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_inputs_are_not_copied(dtype):
    raw = np.ascontiguousarray(unit_square_queries(10)[0], dtype=dtype)
    search = contactnn.LocalSearch("bilinear", "closed_form")
    search.run(raw)
    assert search.last_input_address == raw.ctypes.data
    # A view that is C-contiguous (rows 2..5) is read in place too.
    view = raw[2:6]
    search.run(view)
    assert search.last_input_address == view.ctypes.data
    faces = contactnn.FaceSearch("tri3", "closed_form")
    tri = np.ascontiguousarray(np.column_stack([np.tile([0, 0, 0, 1, 0, 0, 0, 1, 0], (4, 1)),
                                                np.full((4, 3), 0.25)]), dtype=dtype)
    faces.run(tri)
    assert faces.last_input_address == tri.ctypes.data


def test_face_search_tri3_and_tri6():
    tri = np.array([[0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.3, 0.5]])
    param, gap, status = contactnn.FaceSearch("tri3", "closed_form").run(tri)
    assert status[0] == 0 and np.allclose(param[0], [0.2, 0.3], atol=1e-15) and np.isclose(gap[0], 0.5)
    # A flat tri6 (mid-side nodes at the edges' middles) is the same triangle.
    tri6 = np.array([[0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0, 0.2, 0.3, -0.5]])
    param, gap, status = contactnn.FaceSearch("tri6", "newton").run(tri6)
    assert status[0] == 0 and np.allclose(param[0], [0.2, 0.3], atol=1e-12) and np.isclose(gap[0], -0.5)
    with pytest.raises(ValueError, match=r"shape \(1, 12\), expected \(n, 21\)"):
        contactnn.FaceSearch("tri6", "newton").run(tri)


def test_bad_inputs_are_refused():
    search = contactnn.LocalSearch("bilinear", "newton:5")
    raw = unit_square_queries(4)[0]
    with pytest.raises(ValueError, match=r"raw: shape \(4, 14\), expected \(n, 15\)"):
        search.run(raw[:, :14].copy())
    with pytest.raises(ValueError, match=r"raw: shape \(60,\), expected \(n, 15\)"):
        search.run(raw.ravel())
    with pytest.raises(TypeError, match="raw: dtype int64, expected float64 or float32"):
        search.run(raw.astype(np.int64))
    with pytest.raises(ValueError, match="raw: not C-contiguous"):
        search.run(np.asfortranarray(raw))
    with pytest.raises(ValueError, match="not C-contiguous"):
        search.run(np.zeros((4, 30))[:, ::2])
    with pytest.raises(TypeError, match=r"out\[0\] \(param\): dtype float32, expected float64"):
        search.run(raw, out=(np.zeros((4, 2), np.float32), np.zeros(4), np.zeros(4, np.uint8)))
    with pytest.raises(ValueError, match=r"out\[1\] \(gap\): shape \(3,\), expected \(4,\)"):
        search.run(raw, out=(np.zeros((4, 2)), np.zeros(3), np.zeros(4, np.uint8)))
    read_only = np.zeros(4, np.uint8)
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match=r"out\[2\] \(status\): read-only"):
        search.run(raw, out=(np.zeros((4, 2)), np.zeros(4), read_only))
    with pytest.raises(contactnn.InvalidArgument, match="unknown local-search method 'newtn'"):
        contactnn.LocalSearch("bilinear", "newtn")
    with pytest.raises(ValueError, match="network"):
        contactnn.LocalSearch("bilinear", "network")  # a network method without its network
    # A non-finite query is lib/search's status invalid, not an exception: one bad row of a batch does not stop
    # the others (LocalSearch::run's contract).
    raw[1, 13] = np.nan
    param, gap, status = search.run(raw)
    assert contactnn.STATUS_NAMES[status[1]] == "invalid"
    assert all(contactnn.STATUS_NAMES[s] == "ok" for s in status[[0, 2, 3]])


def flat_handle(**options):
    """Two quad4 faces and two tri3 faces on z = 0 (x in [0, 2], y in [0, 2]); slave nodes 6 and 7 above them."""
    x = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0],
                  [0.5, 0.5, 0.25], [1.25, 1.5, -0.125], [0, 2, 0], [2, 2, 0]], float)
    types = ["quad4", "quad4", "tri3", "tri3"]
    connectivity = [0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 8, 4, 9, 8]
    return contactnn.ContactSearch(types, connectivity, len(x), slave_nodes=[6, 7], **options), x


def test_handle_answers_and_out():
    search, x = flat_handle()
    c = search.update(x)
    assert c.status.tolist() == [0, 0] and c.face.tolist() == [0, 3]
    assert c.gap.tolist() == [0.25, -0.125]
    assert np.allclose(c.point, [[0.5, 0.5, 0], [1.25, 1.5, 0]]) and np.allclose(c.normal, [[0, 0, 1], [0, 0, 1]])
    assert search.last_input_address == x.ctypes.data
    out = contactnn.Contacts(2)
    assert search.update(x, out=out) is out
    for name in ("status", "face", "location", "param", "point", "gap", "normal"):
        assert np.array_equal(getattr(out, name), getattr(c, name)), name
    # float32 coordinates: converted to float64 (the handle computes in double), the same answers here.
    assert search.update(x.astype(np.float32)).gap.tolist() == [0.25, -0.125]


def test_handle_bad_inputs():
    search, x = flat_handle()
    with pytest.raises(ValueError, match=r"coordinates: shape \(9, 3\), expected \(10, 3\)"):
        search.update(x[:9].copy())
    with pytest.raises(TypeError, match="coordinates: dtype int64, expected float64 or float32"):
        search.update(x.astype(np.int64))
    with pytest.raises(ValueError, match="coordinates: not C-contiguous"):
        search.update(np.asfortranarray(x))
    out = contactnn.Contacts(2)
    before = out.gap.copy()
    bad = x.copy()
    bad[4, 2] = np.nan
    with pytest.raises(contactnn.NumericalError) as e:
        search.update(bad, out=out)
    assert isinstance(e.value, ArithmeticError) and e.value.exit_code == 5 and "coordinate" in str(e.value)
    assert np.array_equal(out.gap, before, equal_nan=True)  # nothing written
    with pytest.raises(ValueError, match=r"out.status: shape \(3,\), expected \(2,\)"):
        search.update(x, out=contactnn.Contacts(3))
    with pytest.raises(contactnn.InvalidArgument, match="node"):
        contactnn.ContactSearch(["quad4"], [0, 1, 2, 99], 10, slave_nodes=[5])
    with pytest.raises(ValueError, match="face type 'quad9'"):
        contactnn.ContactSearch(["quad9"], [0, 1, 2, 3], 10, slave_nodes=[5])
    search.close()
    assert search.closed
    with pytest.raises(ValueError, match="ContactSearch: the handle is closed"):
        search.update(x)
    with flat_handle()[0] as handle:
        handle.update(x)
    assert handle.closed


def test_handle_method_is_the_local_searchs_and_not_the_exact_search(source_dir):
    """ContactSearch(method=...): on a twisted quad4, points over its interior get LocalSearch's newton:1 answers
    (not the exact search's); a network method takes its network file; a bad method is refused."""
    x = np.array([[0, 0, 0], [1, 0, 0.4], [1, 1, 0], [0, 1, 0.4]], float)
    points = np.array([[0.3 + 0.4 * (i % 3) / 2, 0.3 + 0.4 * (i // 3) / 2, 0.2 if i % 2 else -0.15] for i in range(9)])
    exact = contactnn.ContactSearch(["quad4"], [0, 1, 2, 3], 4, free_points=9).update(x, points)
    c = contactnn.ContactSearch(["quad4"], [0, 1, 2, 3], 4, free_points=9, method="newton:1").update(x, points)
    raw = np.hstack([np.tile(x.reshape(1, 12), (9, 1)), points])
    param, _, status = contactnn.LocalSearch("bilinear", "newton:1").run(raw)
    ok = status == 0
    assert ok.sum() > 4 and np.all(c.status == 0) and np.all(c.location[ok] == 0)
    assert np.max(np.abs(c.param[ok] - param[ok])) < 1e-12
    assert np.max(np.abs(c.param - exact.param)) > 1e-6
    network = os.path.join(source_dir, "data", "weights", "bilinear-8.h5")
    n = contactnn.ContactSearch(["quad4"], [0, 1, 2, 3], 4, free_points=9, method="network+newton:1", network=network)
    assert np.all(n.update(x, points).status == 0)
    with pytest.raises(contactnn.InvalidArgument, match="options.method"):
        contactnn.ContactSearch(["quad4"], [0, 1, 2, 3], 4, free_points=9, method="newton:two")


def test_face_search_with_a_face_network(source_dir):
    """A shipped tri6 network (scene-study --face) in FaceSearch: its estimate refined by Newton is the flat face's
    exact answer; the network of another face type is refused."""
    net = contactnn.read_face_network(os.path.join(source_dir, "data", "weights", "tri6-48-48.h5"))
    assert net.face == "tri6"
    tri6 = np.array([[0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0, 0.2, 0.3, -0.1]])
    estimate = contactnn.FaceSearch("tri6", "network", network=net).run(tri6)[0]
    assert np.max(np.abs(estimate - [0.2, 0.3])) < 0.05
    param, gap, status = contactnn.FaceSearch("tri6", "network+newton:3", network=net).run(tri6)
    assert status[0] == 0 and np.allclose(param, [[0.2, 0.3]], atol=1e-12) and np.isclose(gap[0], -0.1)
    with pytest.raises(contactnn.InvalidArgument, match="tri6 network"):
        contactnn.FaceSearch("quad8", "network", network=net)
