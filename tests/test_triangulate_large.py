"""Triangulation of one huge polygon (a 20,000-corner face): complete and valid against numpy's own
shoelace area and boundary-chain check, through the API, mesh_info and the CLI (docs/mesh_model.md)."""
import json
import subprocess
import sys

import numpy as np
import pytest

import meshmark

N = 20000


def star(n: int, seed: int = 0) -> np.ndarray:
    """(n, 2) counter-clockwise star: radii alternate between an outer (jittered) and an inner ring."""
    rng = np.random.default_rng(seed)
    t = 2 * np.pi * np.arange(n) / n
    r = np.where(np.arange(n) % 2, 0.5, 1.0) + rng.uniform(0, 0.3, n)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def shoelace(q: np.ndarray) -> float:
    x, y = q[:, 0], q[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def in_plane(q: np.ndarray) -> np.ndarray:
    """The 2-D polygon placed in a tilted plane far from the origin: (n, 3)."""
    e1 = np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
    e2 = np.array([1.0, 1.0, -2.0]) / np.sqrt(6)
    return np.array([300.0, -200.0, 100.0]) + q[:, :1] * e1 + q[:, 1:] * e2


def boundary_chain_is_the_polygon(T: np.ndarray, n: int) -> bool:
    """The directed triangle edges, opposite ones cancelling, leave exactly the polygon's edges."""
    e = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]).astype(np.int64)
    sign = np.where(e[:, 0] < e[:, 1], 1, -1)
    key = np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1])
    poly = np.column_stack([np.arange(n), (np.arange(n) + 1) % n]).astype(np.int64)
    psign = np.where(poly[:, 0] < poly[:, 1], -1, 1)
    pkey = np.minimum(poly[:, 0], poly[:, 1]) * n + np.maximum(poly[:, 0], poly[:, 1])
    keys, inv = np.unique(np.concatenate([key, pkey]), return_inverse=True)
    total = np.bincount(inv, weights=np.concatenate([sign, psign]), minlength=len(keys))
    return bool(np.all(total == 0))


@pytest.fixture(scope="module")
def star_face():
    q = star(N, seed=1)
    return q, meshmark.Mesh.from_polygons(in_plane(q), np.arange(N, dtype=np.int32), np.array([0, N]))


def test_20000_corner_star_is_tiled(star_face):
    q, m = star_face
    T, face = meshmark.triangulate(m)
    assert T.shape == (N - 2, 3) and np.all(face == 0)
    assert np.array_equal(np.unique(T), np.arange(N))  # every corner used
    assert boundary_chain_is_the_polygon(T, N)
    # every triangle turns the polygon's way in the plane: with the chain, they tile the polygon
    a, b, c = q[T[:, 0]], q[T[:, 1]], q[T[:, 2]]
    signed = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    assert np.all(signed > 0)
    # areas in 3-D (meshmark's, from the 3-D corners) add up to the shoelace area of the 2-D polygon
    area = shoelace(q)
    assert meshmark.face_areas(m.V, T).sum() == pytest.approx(area, rel=1e-9)
    assert meshmark.mesh_info(m)["surface_area"] == pytest.approx(area, rel=1e-9)


def test_large_convex_polygon_is_the_fan_from_corner_0():
    n = 5000
    t = 2 * np.pi * np.arange(n) / n
    m = meshmark.Mesh.from_polygons(in_plane(np.column_stack([np.cos(t), np.sin(t)])), np.arange(n), np.array([0, n]))
    T, _ = meshmark.triangulate(m)
    expect = np.column_stack([np.zeros(n - 2, int), np.arange(1, n - 1), np.arange(2, n)])
    assert np.array_equal(T, expect)


@pytest.mark.parametrize("kind", ["self-intersecting", "collinear", "one point", "saddle"])
def test_hostile_large_polygons_terminate_complete(kind):
    n = 20000
    rng = np.random.default_rng(2)
    if kind == "self-intersecting":  # random corners: crosses itself everywhere
        V = np.column_stack([rng.uniform(-1, 1, (n, 2)), np.zeros(n)])
    elif kind == "collinear":  # every corner on one line, back and forth
        x = np.concatenate([np.linspace(0, 1, n // 2), np.linspace(1, 0, n // 2)])
        V = np.column_stack([x, 2 * x, 3 * x])
    elif kind == "one point":
        V = np.tile([0.5, 0.25, 1.0], (n, 1))
    else:  # a star on a saddle: not planar
        q = star(n, seed=3)
        V = np.column_stack([q, 0.3 * (q[:, 0] ** 2 - q[:, 1] ** 2)])
    m = meshmark.Mesh.from_polygons(V, np.arange(n), np.array([0, n]), validate=False)
    T, face = meshmark.triangulate(m)
    assert T.shape == (n - 2, 3)
    assert np.array_equal(np.unique(T), np.arange(n))
    assert boundary_chain_is_the_polygon(T, n)  # a triangulation of the ring, if not of its interior


def test_cli_info_on_a_20000_corner_obj(tmp_path, star_face):
    q, m = star_face
    path = tmp_path / "star.obj"
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in m.V]
    path.write_text("\n".join(lines) + "\nf " + " ".join(str(i + 1) for i in range(N)) + "\n")
    out = subprocess.run([sys.executable, "-m", "meshmark.cli", "info", str(path), "--json"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    assert d["n_faces"] == 1 and d["n_degenerate_faces"] == 0 and d["face_sizes"] == {str(N): 1}
    assert d["surface_area"] == pytest.approx(shoelace(q), rel=1e-9)
