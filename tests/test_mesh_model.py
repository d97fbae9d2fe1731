"""The mesh model and per-mesh quantities, against hand-computed values and numpy/scipy."""
import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as scipy_cc

import meshmark
from meshmark import Mesh, MeshError
from meshmark.shapes import torus, cylinder, default_mesh


def numpy_edges(F):
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E.sort(axis=1)
    return np.unique(E, axis=0, return_counts=True)


from conftest import random_rotation  # noqa: E402


def test_mesh_from_arrays_and_polygons():
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    m = Mesh(V, [[0, 1, 2, 3], [1, 4, 2]])
    assert m.n_faces == 2 and m.face_sizes.tolist() == [4, 3]
    assert m.face_offsets.tolist() == [0, 4, 7]
    with pytest.raises(MeshError, match="mixes polygons of 3 to 4"):
        m.F
    T = m.triangles
    assert T.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    assert meshmark.triangulate(m)[1].tolist() == [0, 0, 1]
    q = Mesh(V[:4], np.array([[0, 1, 2, 3]], dtype=np.int64))
    assert q.F.dtype == np.int32 and q.F.shape == (1, 4)
    assert meshmark.unique_edges(q)[0].shape == (4, 2)  # sides only, no diagonal


def test_unique_edges_match_numpy(bunny):
    T = bunny.F
    E, cnt = meshmark.unique_edges(bunny)
    E2, cnt2 = numpy_edges(T)
    np.testing.assert_array_equal(E, E2)
    np.testing.assert_array_equal(cnt, cnt2)
    assert len(meshmark.boundary_edges(bunny)) == 223  # SOURCES.md
    val = meshmark.valence(bunny)
    np.testing.assert_array_equal(val, np.bincount(E2.ravel(), minlength=bunny.n_vertices))


def test_adjacency_is_csr_of_the_edge_graph(bunny):
    ptr, nbr = meshmark.vertex_adjacency(bunny)
    E, _ = meshmark.unique_edges(bunny)
    n = bunny.n_vertices
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n))
    A = (A + A.T).tocsr()
    A.sort_indices()
    np.testing.assert_array_equal(ptr, A.indptr)
    np.testing.assert_array_equal(nbr, A.indices)


def test_components_match_scipy():
    m = meshmark.read_mesh(__import__("conftest").shared_mesh("classic/teapot.obj"))
    labels, count = meshmark.connected_components(m)
    E, _ = meshmark.unique_edges(m)
    n = m.n_vertices
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n))
    referenced = np.zeros(n, bool)
    referenced[m.face_indices] = True
    k, lab = scipy_cc(A, directed=False)
    assert count == 4  # SOURCES.md: 4 components
    assert count == len(np.unique(lab[referenced]))
    # same partition
    pairs = np.unique(np.stack([labels[referenced], lab[referenced]], 1), axis=0)
    assert len(pairs) == count


def test_normals_areas_angles_match_numpy(bunny):
    V, T = bunny.V, bunny.F
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    cr = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(cr, axis=1)
    np.testing.assert_allclose(meshmark.face_areas(bunny), area, rtol=1e-12, atol=0)
    np.testing.assert_allclose(meshmark.face_normals(bunny), cr / (2 * area[:, None]), atol=1e-12)
    ang = meshmark.interior_angles(bunny)
    np.testing.assert_allclose(ang.sum(1), np.pi, atol=1e-9)
    u, w = b - a, c - a
    ref = np.arccos(np.clip((u * w).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1), -1, 1))
    np.testing.assert_allclose(ang[:, 0], ref, atol=1e-6)
    s = meshmark.angle_sum(bunny)
    np.testing.assert_allclose(s, np.bincount(T.ravel(), ang.ravel(), minlength=bunny.n_vertices), atol=1e-12)


def test_gauss_bonnet_on_closed_torus():
    m = torus()
    deficit = 2 * np.pi - meshmark.angle_sum(m)
    assert abs(deficit.sum()) < 1e-9  # genus 1: total curvature 2*pi*chi = 0
    info = meshmark.mesh_info(m)
    assert info["euler_characteristic"] == 0 and info["closed"] and info["manifold"]


def test_dihedral_angles_of_cylinder():
    seg = 32
    m = cylinder(segments=seg, rings=4, capped=False)
    E, ang = meshmark.dihedral_angles(m)
    finite = ang[~np.isnan(ang)]
    # around the tube, neighbouring faces of a quad strip meet at 2*pi/seg; diagonals are flat
    assert np.isclose(finite.max(), 2 * np.pi / seg, atol=1e-9)
    assert np.isclose(finite.min(), 0, atol=1e-9)
    assert np.isnan(ang).sum() == 2 * seg  # the two open rims


def test_pca_matches_numpy_and_is_invariant(bunny, rng):
    V = bunny.V
    p = meshmark.pca(V)
    C = np.cov(V.T, bias=True)
    w, Q = np.linalg.eigh(C)
    np.testing.assert_allclose(p["eigenvalues"], w[::-1], rtol=1e-9)
    for k in range(3):
        assert abs(abs(p["axes"][:, k] @ Q[:, 2 - k]) - 1) < 1e-9
    assert (p["skewness"] >= 0).all()
    # Invariance: rotate + translate + scale + permute: axes follow the rotation exactly.
    R = random_rotation(rng)
    W = (2.5 * V @ R.T + [3, -1, 7])[rng.permutation(len(V))]
    p2 = meshmark.pca(W)
    np.testing.assert_allclose(p2["axes"], R @ p["axes"], atol=1e-7)
    np.testing.assert_allclose(p2["centroid"], 2.5 * R @ p["centroid"] + [3, -1, 7], atol=1e-9)


def test_mesh_info_of_builtin_default():
    d = meshmark.mesh_info(default_mesh())
    assert (d["n_vertices"], d["n_faces"], d["n_edges"]) == (4608, 9216, 13824)
    assert d["n_boundary_edges"] == 0 and d["n_components"] == 1 and d["manifold"]


def test_non_manifold_detection():
    V = np.eye(5, 3) * [1, 2, 3] + np.arange(15).reshape(5, 3) * 0.01
    bowtie = Mesh(V, [[0, 1, 2], [0, 3, 4]])
    r = meshmark.manifold_report(bowtie)
    assert r["non_manifold_vertices"] == 1 and r["edge_manifold"] and not r["manifold"]
    fin = Mesh(V, [[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    assert meshmark.manifold_report(fin)["non_manifold_edges"] == 1
