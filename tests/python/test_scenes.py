"""The contact search handle from Python against gen-configs --scene (SPEC 9) on make-scene's example decks, and a
CalculiX run replayed through its increments against gen-configs --results --increment all: the same slave nodes,
statuses, faces (their nodes), locations, closest points and gaps, to the last bit."""

import os
import shutil
import subprocess

import numpy as np
import pytest

import contactnn
from conftest import read_csv, run_tool

DECKS = [("hertz", 0), ("hertz", 1), ("cylinders", 0), ("flat", 0), ("flat", 1), ("forming", 0)]


def face_nodes(scene):
    """Each face's node ids, as the tuple gen-configs writes in its `nodes` column."""
    counts = {"quad4": 4, "quad8": 8, "tri3": 3, "tri6": 6}
    out, at = [], 0
    for t in scene.face_types:
        n = counts[contactnn.FACE_TYPES[t]]
        out.append(tuple(int(v) for v in scene.connectivity[at:at + n]))
        at += n
    return out


def compare(rows, scene, contacts, where, tolerance=0.0):
    """gen-configs' rows (one per slave node, increasing id) against the handle's answers: bit for bit, or points and
    gaps to `tolerance` times (1 + |P|) (replay's test of tracking against a fresh search)."""
    faces = face_nodes(scene)
    assert len(rows) == len(scene.slave_ids), where
    found = 0
    for i, row in enumerate(rows):
        at = f"{where}, slave {row['slave']}"
        assert int(row["slave"]) == scene.slave_ids[i], at
        if row["status"] == "no_segment":
            assert contacts.status[i] == 6 and contacts.face[i] == -1, at
            continue
        found += 1
        assert contacts.status[i] == 0, at
        assert faces[contacts.face[i]] == tuple(int(v) for v in row["nodes"].split()), at
        assert contactnn.LOCATION_NAMES[contacts.location[i]] == row["location"], at
        point = [float(row[k]) for k in ("px", "py", "pz")]
        if tolerance == 0.0:
            assert contacts.point[i].tolist() == point, at
            assert contacts.gap[i] == float(row["gap"]), at
        else:
            slack = tolerance * (1.0 + np.linalg.norm(point))
            assert np.linalg.norm(contacts.point[i] - point) <= slack, at
            assert abs(contacts.gap[i] - float(row["gap"])) <= slack, at
    assert found > 0, where


@pytest.mark.parametrize("surface", ["bilinear", "gregory"])
@pytest.mark.parametrize("deck,pair", DECKS)
def test_handle_is_gen_configs_scene(deck, pair, surface, scenes_dir, gen_configs, tmp_path):
    path = os.path.join(scenes_dir, deck + ".inp")
    scene = contactnn.read_deck(path).scene(pair)
    if surface == "gregory" and any(
            contactnn.FACE_TYPES[t] == "quad4" and not s for t, s in zip(scene.face_types, scene.face_segments)):
        pytest.skip("C3D6 quadrilaterals: bilinear facets in a deck's Gregory search, Gregory patches in the handle's")
    out = tmp_path / "pairs.csv"
    run_tool([gen_configs, "--scene", path, "--pair", str(pair), "--surface", surface, "--output", str(out)])
    search = contactnn.contact_search(scene, quad4=surface)
    compare(read_csv(out), scene, search.update(scene.coordinates()), f"{deck} pair {pair} {surface}")


def test_replay_is_gen_configs_results(histories_dir, gen_configs, tmp_path):
    """hertz-slide through ccx, every increment: the handle against gen-configs --increment all, bit for bit without
    tracking; with tracking (a warm start from the previous point) the same faces, points and gaps to 1e-12."""
    if shutil.which("ccx") is None:
        pytest.skip("ccx not installed (apt-get install calculix-ccx)")
    shutil.copy(os.path.join(histories_dir, "hertz-slide.inp"), tmp_path / "run.inp")
    r = subprocess.run(["ccx", "-i", "run"], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0 and (tmp_path / "run.frd").exists(), r.stdout[-2000:]
    out = tmp_path / "history.csv"
    run_tool([gen_configs, "--scene", str(tmp_path / "run.inp"), "--results", str(tmp_path / "run.frd"),
              "--increment", "all", "--output", str(out)])
    rows = read_csv(out)

    # The replay, as docs/python.md writes it.
    scene = contactnn.read_deck(str(tmp_path / "run.inp")).scene(0)
    results = contactnn.read_results(str(tmp_path / "run.frd"))
    fresh = contactnn.contact_search(scene, tracking=False)
    tracked = contactnn.contact_search(scene)
    assert results.increment_count >= 2
    reused = 0
    for n in range(1, results.increment_count + 1):
        x = scene.coordinates(results, n)
        expected = [row for row in rows if int(row["increment"]) == n]
        compare(expected, scene, fresh.update(x), f"increment {n}")
        compare(expected, scene, tracked.update(x), f"increment {n}, tracked", tolerance=1e-12)
        reused += tracked.counts["tracked"] + tracked.counts["warm"]
    assert reused > 0, "tracking never reused a list"


def test_scene_coordinates_are_the_decks(scenes_dir):
    scene = contactnn.read_deck(os.path.join(scenes_dir, "flat.inp")).scene(0)
    x = scene.coordinates()
    assert x.shape == (len(scene.node_ids), 3) and x.dtype == np.float64
    assert np.all(np.diff(scene.node_ids) > 0)
    assert set(scene.slave_ids) <= set(scene.node_ids.tolist())
    assert set(scene.connectivity.tolist()) <= set(scene.node_ids.tolist())
