"""Attacks (meshmark.attacks): hand-computed answers on tiny meshes, then properties (seeds, invariances,
bounds) and bad input. Shared meshes are read through conftest.shared_mesh (fail, never skip)."""
import math
import subprocess
import sys

import numpy as np
import pytest

import meshmark
from meshmark import MeshError, attacks as A, metrics as M
from conftest import shared_mesh

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])

# a square pyramid fan: apex 0 above the centre, 4 rim vertices, open at the bottom
FAN_V = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
FAN_F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]])

OCT_V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
OCT_F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])


def grid_quads(n=3):
    """(n+1)^2 vertices on the unit square, n^2 quads (a polygon mesh)."""
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    V = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], 1)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    return V, np.stack([a, a + n + 1, a + n + 2, a + 1], 1)


@pytest.fixture(scope="module")
def cow():
    return meshmark.read_mesh(shared_mesh("classic/cow.obj"))


# --- similarity and reordering ------------------------------------------------------------------------

def test_rotate_translate_scale_by_hand():
    r = A.rotate(TET_V, TET_F, axis=(0, 0, 1), angle=90)
    np.testing.assert_allclose(r.V[1], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(r.V[2], [-1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(r.V[3], [0, 0, 1], atol=1e-15)
    # about a centre: (1,0,0) rotated 180 deg about the z axis through (1,1,0) -> (1,2,0)
    r = A.rotate(TET_V, TET_F, axis=(0, 0, 2), angle=180, center=(1, 1, 0))
    np.testing.assert_allclose(r.V[1], [1, 2, 0], atol=1e-14)
    np.testing.assert_array_equal(A.translate(TET_V, TET_F, offset=(1, 2, 3)).V[3], [1, 2, 4])
    np.testing.assert_allclose(A.scale(TET_V, TET_F, factor=2, center=(1, 0, 0)).V[0], [-1, 0, 0])
    np.testing.assert_array_equal(r.F, TET_F)


def test_random_similarity_is_a_similarity_and_seeded(cow):
    out, R, s, t = A.similarity(cow, seed=7, return_transform=True)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert abs(np.linalg.det(R) - 1) < 1e-14
    assert 0.5 <= s <= 2.0
    np.testing.assert_allclose(out.V, s * cow.V @ R.T + t, rtol=0, atol=1e-12)
    # pairwise distances scale by s
    d0 = np.linalg.norm(cow.V[10] - cow.V[2000])
    assert abs(np.linalg.norm(out.V[10] - out.V[2000]) - s * d0) < 1e-12 * s * d0 * 10
    again = A.similarity(cow, seed=7)
    np.testing.assert_array_equal(again.V, out.V)
    assert not np.array_equal(A.similarity(cow, seed=8).V, out.V)
    # t = U[-1, 1]^3 * translation * bbox diagonal (of the referenced vertices): 40 seeds fill the cube
    used = np.zeros(cow.n_vertices, bool)
    used[cow.face_indices] = True
    diag = np.linalg.norm(cow.V[used].max(0) - cow.V[used].min(0))
    u = np.array([A.similarity(cow, seed=k, translation=0.25, return_transform=True)[3] for k in range(40)]) / (0.25 * diag)
    assert np.abs(u).max() <= 1.0 and np.abs(u).max() > 0.95  # measured 0.995
    assert abs(u.mean()) < 0.15 and abs(u.std() - 3 ** -0.5) < 0.06  # U[-1, 1]: 0, 0.577; measured -0.07, 0.573


def test_random_rotation_is_uniform_on_average():
    # E[R] = 0 for the Haar measure; the mean of 4000 draws is O(1/sqrt(4000))
    Rs = np.stack([A.random_rotation(s) for s in range(4000)])
    assert np.abs(Rs.mean(0)).max() < 0.05
    np.testing.assert_allclose(np.einsum("kij,kil->kjl", Rs, Rs), np.broadcast_to(np.eye(3), Rs.shape), atol=1e-13)


def test_reorder_reindexes_faces_consistently(cow):
    out, vp, fp = A.reorder(cow, seed=3, return_permutations=True)
    assert sorted(vp) == list(range(cow.n_vertices)) and sorted(fp) == list(range(cow.n_faces))
    assert not np.array_equal(vp, np.arange(cow.n_vertices))
    np.testing.assert_array_equal(out.V, cow.V[vp])
    np.testing.assert_array_equal(vp[out.F], cow.F[fp])  # same corners, same winding
    again = A.reorder(cow, seed=3)
    np.testing.assert_array_equal(again.F, out.F)
    only_v, vp2, fp2 = A.reorder(cow, seed=3, faces=False, return_permutations=True)
    np.testing.assert_array_equal(fp2, np.arange(cow.n_faces))
    np.testing.assert_array_equal(vp2[only_v.F], cow.F)


def test_reorder_keeps_polygons():
    V, Q = grid_quads(3)
    out, vp, fp = A.reorder(V, Q, seed=1, return_permutations=True)
    assert (out.face_sizes == 4).all()
    np.testing.assert_array_equal(vp[out.F], Q[fp])


def test_permutation_and_similarity_leave_the_distortion_unchanged(cow):
    """Metrics are invariant where they should be: reorder both meshes the same way, or move both by
    the same similarity."""
    noisy = A.noise(cow, strength=0.0025, seed=1)
    nd = M.normal_degradation(cow, noisy, weighting="area")
    _, vp, fp = A.reorder(cow, seed=5, return_permutations=True)
    inv = np.argsort(vp)
    F2 = inv[cow.F[fp]]
    nd_p = M.normal_degradation(cow.V[vp], noisy.V[vp], F2, weighting="area")
    assert abs(nd_p - nd) < 1e-12
    _, R, s, t = A.similarity(cow, seed=2, return_transform=True)
    S = lambda X: s * X @ R.T + t
    assert abs(M.normal_degradation(S(cow.V), S(noisy.V), cow.F, weighting="area") - nd) < 1e-9
    sd = M.surface_distance(cow, noisy, seed=4)
    sd_s = M.surface_distance((S(cow.V), cow.F), (S(noisy.V), cow.F), seed=4)
    # absolute distances scale by s (the *_rel values use the axis-aligned box, which a rotation changes)
    assert abs(sd_s["hausdorff"] / (s * sd["hausdorff"]) - 1) < 1e-9
    assert abs(sd_s["rms"] / (s * sd["rms"]) - 1) < 1e-9
    assert abs(M.vertex_rmse(S(cow.V), S(noisy.V)) - s * M.vertex_rmse(cow, noisy)) < 1e-12
    # a reordered copy is at distance 0 from the original
    sd0 = M.surface_distance(cow, A.reorder(cow, seed=9), n_samples=2000)
    assert sd0["hausdorff"] < 1e-12 * sd0["diag"]


# --- noise --------------------------------------------------------------------------------------------

def test_mean_centroid_distance_by_hand():
    dbar = (math.sqrt(3) / 4 + 3 * math.sqrt(0.75 ** 2 + 2 * 0.25 ** 2)) / 4
    assert abs(A.mean_centroid_distance(TET_V, TET_F) - dbar) < 1e-15
    # an unreferenced vertex does not count when F is given
    V = np.vstack([TET_V, [[100, 100, 100]]])
    assert abs(A.mean_centroid_distance(V, TET_F) - dbar) < 1e-15


def test_uniform_noise_bounds_statistics_and_seed(cow):
    A_ = 0.005
    dbar = A.mean_centroid_distance(cow)
    out = A.noise(cow, strength=A_, seed=11)
    D = out.V - cow.V
    assert np.abs(D).max() <= A_ * dbar * (1 + 1e-12)                 # eq. 6.3.12: |a_i| <= A
    assert np.abs(D).max() > 0.99 * A_ * dbar
    # U[-A d, A d]: mean 0, variance (A d)^2 / 3, for 3 * 2903 draws
    assert abs(D.mean()) < 0.05 * A_ * dbar
    assert abs(D.var() / ((A_ * dbar) ** 2 / 3) - 1) < 0.05
    np.testing.assert_array_equal(A.noise(cow, strength=A_, seed=11).V, out.V)
    assert not np.array_equal(A.noise(cow, strength=A_, seed=12).V, out.V)
    np.testing.assert_array_equal(A.noise(cow, strength=0.0, seed=11).V, cow.V)


def test_gaussian_normal_tangent_noise(cow):
    dbar = A.mean_centroid_distance(cow)
    g = A.noise(cow, strength=0.002, seed=1, kind="gaussian").V - cow.V
    assert abs(g.std() / (0.002 * dbar) - 1) < 0.05 and abs(g.mean()) < 0.05 * 0.002 * dbar
    N = A.vertex_normals(cow)
    dn = A.noise(cow, strength=0.002, seed=1, kind="normal").V - cow.V
    # along the normal only: dn = a n with |a| <= A d
    a = np.sum(dn * N, 1)
    np.testing.assert_allclose(dn, a[:, None] * N, atol=1e-15)
    assert np.abs(a).max() <= 0.002 * dbar * (1 + 1e-12) and np.abs(a).max() > 0.9 * 0.002 * dbar
    dt = A.noise(cow, strength=0.002, seed=1, kind="tangent").V - cow.V
    assert np.abs(np.sum(dt * N, 1)).max() < 1e-15
    assert np.linalg.norm(dt, axis=1).mean() > 0.3 * 0.002 * dbar


def test_vertex_normals_by_hand():
    N = A.vertex_normals(FAN_V, FAN_F)
    np.testing.assert_allclose(N[0], [0, 0, 1], atol=1e-15)
    # rim vertex 1 (1,0,0): faces (0,1,2) and (0,4,1) with normals (1,1,1) and (1,-1,1)
    np.testing.assert_allclose(N[1], np.array([2, 0, 2]) / math.sqrt(8), atol=1e-15)


def test_noise_leaves_unreferenced_vertices():
    V = np.vstack([TET_V, [[5, 5, 5]]])
    out = A.noise(V, TET_F, strength=0.01, seed=0)
    np.testing.assert_array_equal(out.V[4], [5, 5, 5])
    assert not np.array_equal(out.V[:4], TET_V)


# --- smoothing ----------------------------------------------------------------------------------------

def test_uniform_smoothing_one_step_by_hand():
    out = A.smooth(FAN_V, FAN_F, lam=0.5, iterations=1)
    np.testing.assert_allclose(out.V[0], [0, 0, 0.5])          # apex: mean of the rim is the origin
    # rim vertex (1,0,0): neighbours apex, (0,1,0), (0,-1,0): mean (0, 0, 1/3)
    np.testing.assert_allclose(out.V[1], [0.5, 0, 1 / 6])
    two = A.smooth(FAN_V, FAN_F, lam=0.5, iterations=2)
    one = out.V
    nb = {0: [1, 2, 3, 4], 1: [0, 2, 4]}
    np.testing.assert_allclose(two.V[0], one[0] + 0.5 * (one[nb[0]].mean(0) - one[0]), atol=1e-15)
    np.testing.assert_allclose(two.V[1], one[1] + 0.5 * (one[nb[1]].mean(0) - one[1]), atol=1e-15)


def test_smoothing_lambda_zero_is_identity(cow):
    for w in ("uniform", "cotangent"):
        np.testing.assert_array_equal(A.smooth(cow, lam=0.0, iterations=30, weights=w).V, cow.V)
        np.testing.assert_array_equal(A.smooth(cow, lam=0.5, iterations=0, weights=w).V, cow.V)


def test_smoothing_uses_the_polygon_edge_graph():
    V, Q = grid_quads(2)      # 3x3 grid: centre vertex 4 has the 4 edge neighbours 1, 3, 5, 7 (no diagonals)
    V = V.copy()
    V[4, 2] = 1.0
    out = A.smooth(V, Q, lam=1.0, iterations=1)
    np.testing.assert_allclose(out.V[4], [0.5, 0.5, 0.0], atol=1e-15)
    # corner 0 has neighbours 1 and 3 only
    np.testing.assert_allclose(out.V[0], (V[1] + V[3]) / 2, atol=1e-15)
    assert (out.face_sizes == 4).all()


def test_cotangent_smoothing_by_hand():
    # symmetric fan: every weight of the apex is equal, so the apex moves straight down by lam * h
    out = A.smooth(FAN_V, FAN_F, lam=0.25, iterations=1, weights="cotangent")
    np.testing.assert_allclose(out.V[0], [0, 0, 0.75], atol=1e-15)
    # planar regular patch: the interior vertex of a symmetric flat fan stays put
    flat = FAN_V.copy()
    flat[0, 2] = 0
    out = A.smooth(flat, FAN_F, lam=0.5, iterations=3, weights="cotangent", fix_boundary=True)
    np.testing.assert_allclose(out.V, flat, atol=1e-15)


def test_smoothing_shrinks_and_fix_boundary(cow):
    s = A.smooth(cow, lam=0.02, iterations=50)
    assert 0 < M.vertex_rmse(cow, s) < 0.01 * M.bbox_diagonal(cow)
    V, F = FAN_V, FAN_F
    out = A.smooth(V, F, lam=0.5, iterations=5, fix_boundary=True)
    np.testing.assert_array_equal(out.V[1:], V[1:])


# --- quantization -------------------------------------------------------------------------------------

def test_quantize_by_hand():
    V = np.array([[0, 0, 0], [1, 2, 0], [0.3, 0.375, 0], [0.38, 1.9, 0]], float)
    out = A.quantize(V, [[0, 1, 2]], bits=2).V        # steps 0.25 in x, 0.5 in y; z has zero extent
    np.testing.assert_allclose(out[2], [0.25, 0.5, 0])   # 0.375 in y: 0.75 steps -> 1 step
    np.testing.assert_allclose(out[3], [0.5, 2.0, 0])
    tie = A.quantize(np.array([[0, 0, 0], [1, 1, 1], [0.375, 0.5, 0.5]]), [[0, 1, 2]], bits=2).V
    np.testing.assert_allclose(tie[2], [0.25, 0.5, 0.5])   # x: exactly half a step -> down


@pytest.mark.parametrize("bits", range(7, 13))
def test_quantize_error_at_most_half_a_step(cow, bits):
    out = A.quantize(cow, bits=bits).V
    step = (cow.V.max(0) - cow.V.min(0)) / 2 ** bits
    err = np.abs(out - cow.V)
    assert (err <= 0.5 * step * (1 + 1e-9)).all()
    assert err.max() > 0.4 * step.min()
    k = (out - cow.V.min(0)) / step                       # on the grid
    np.testing.assert_allclose(k, np.round(k), atol=1e-6)
    assert len(np.unique(out[:, 0])) <= 2 ** bits + 1


def test_dither_bits_by_hand():
    V = np.array([[0, 0, 0], [1, 1, 1], [0.75, 0.25, 0.5]])
    z = np.zeros((3, 3), np.uint64)
    # fixed32, t = 1: keep the top bit of q = floor(x * 2^32) (x = 1 is clamped to 2^32 - 1)
    np.testing.assert_array_equal(A.dither_bits(V, 1, z, "fixed32")[1:], [[0.5, 0.5, 0.5], [0.5, 0, 0.5]])
    ones = np.full((3, 3), np.iinfo(np.uint64).max, np.uint64)
    np.testing.assert_allclose(A.dither_bits(V, 31, ones, "fixed32")[0], [2 ** -32] * 3)
    # float64: 1.75 = 0x3FFC000000000000; keeping 12 bits (sign + exponent) and zeroing the rest -> 1.0
    X = np.array([[1.75, -1.75, 3.0]])
    np.testing.assert_array_equal(A.dither_bits(X, 12, np.zeros((1, 3), np.uint64), "float64"), [[1.0, -1.0, 2.0]])
    np.testing.assert_array_equal(A.dither_bits(X, 13, np.zeros((1, 3), np.uint64), "float64"), [[1.5, -1.5, 3.0]])
    np.testing.assert_array_equal(A.dither_bits(X, 64, np.ones((1, 3), np.uint64), "float64"), X)
    # per-vertex t
    out = A.dither_bits(V, np.array([32, 1, 1]), z, "fixed32")
    np.testing.assert_array_equal(out[0], [0, 0, 0])


def test_dithered_quantize_error_bound_and_seed(cow):
    L = (cow.V.max(0) - cow.V.min(0)).max()
    for t in (8, 12, 20):
        out = A.dithered_quantize(cow, t, seed=3)
        err = np.abs(out - cow.V)
        assert err.max() < L * 2.0 ** -t and err.max() > 0.5 * L * 2.0 ** -t
        np.testing.assert_array_equal(A.dithered_quantize(cow, t, seed=3), out)
    f = A.dithered_quantize(cow, 40, seed=1, word="float64")
    rel = np.abs(f - cow.V) / np.maximum(np.abs(cow.V), 1e-300)
    assert rel.max() < 2.0 ** -(40 - 12 - 1)


# --- connectivity-changing attacks --------------------------------------------------------------------

def test_midpoint_subdivision_by_hand():
    out = A.subdivide(TET_V[:3], [[0, 1, 2]], scheme="midpoint")
    assert out.n_vertices == 6 and out.n_faces == 4
    # edges in unique_edges order: (0,1), (0,2), (1,2)
    np.testing.assert_array_equal(out.V[3:], [[0.5, 0, 0], [0, 0.5, 0], [0.5, 0.5, 0]])
    np.testing.assert_array_equal(out.F, [[0, 3, 4], [1, 5, 3], [2, 4, 5], [3, 5, 4]])
    assert abs(meshmark.face_areas(out).sum() - 0.5) < 1e-15


def test_loop_subdivision_by_hand():
    out = A.subdivide(OCT_V, OCT_F, scheme="loop")
    assert out.n_vertices == 6 + 12 and out.n_faces == 32
    # valence 4: beta = (5/8 - (3/8)^2) / 4 = 31/256; the neighbours of (1,0,0) sum to 0
    np.testing.assert_allclose(out.V[0], [1 - 4 * 31 / 256, 0, 0], atol=1e-15)
    # edge (0,2) = (1,0,0)-(0,1,0): opposite vertices (0,0,+-1): 3/8 (1,1,0)
    E, _ = meshmark.unique_edges(OCT_V, OCT_F)
    e = int(np.nonzero((E[:, 0] == 0) & (E[:, 1] == 2))[0][0])
    np.testing.assert_allclose(out.V[6 + e], [0.375, 0.375, 0], atol=1e-15)
    # boundary rules on a single triangle: corners 3/4 v + 1/8 (p + q), edge midpoints
    tri = A.subdivide(TET_V[:3], [[0, 1, 2]], scheme="loop")
    np.testing.assert_allclose(tri.V[0], [0.125, 0.125, 0], atol=1e-15)
    np.testing.assert_allclose(tri.V[1], [0.75, 0.125, 0], atol=1e-15)
    np.testing.assert_allclose(tri.V[3:], [[0.5, 0, 0], [0, 0.5, 0], [0.5, 0.5, 0]], atol=1e-15)


def test_subdivision_triangulates_polygons():
    V, Q = grid_quads(2)
    out = A.subdivide(V, Q, scheme="midpoint")
    assert out.is_triangle_mesh and out.n_faces == 4 * 2 * 4


def test_crop_by_hand():
    V, Q = grid_quads(3)                        # x in {0, 1/3, 2/3, 1}
    out, kept = A.crop(V, Q, fraction=0.3, normal=(1, 0, 0), return_kept=True)
    # threshold 0.7: the column of quads between x = 2/3 and 1 goes, and the 4 vertices at x = 1
    assert out.n_faces == 6 and out.n_vertices == 12
    np.testing.assert_array_equal(kept, np.arange(12))
    assert (out.face_sizes == 4).all() and out.V[:, 0].max() < 0.7
    out = A.crop(V, Q, fraction=0.3, normal=(-1, 0, 0))
    assert out.V[:, 0].min() > 0.3
    np.testing.assert_array_equal(A.crop(V, Q, fraction=0.0).V, V)


def test_simplify_reaches_the_target(cow):
    for fr in (0.9, 0.5, 0.25):
        out = A.simplify(cow, fraction=fr)
        target = round(fr * cow.n_faces)
        assert target - 2 <= out.n_faces <= target, (fr, out.n_faces, target)
        assert out.is_triangle_mesh
        assert M.surface_distance(cow, out, n_samples=5000)["hausdorff_rel"] < 0.02
    np.testing.assert_equal(A.simplify(cow, fraction=1.0).n_faces, cow.n_faces)


def test_storage_round_trips(cow):
    f = A.float32_cast(cow)
    np.testing.assert_array_equal(f.V, cow.V.astype(np.float32).astype(np.float64))
    obj = A.file_roundtrip(cow, format="obj")
    assert np.abs(obj.V - cow.V).max() <= 5e-7 + 1e-12
    np.testing.assert_array_equal(obj.F, cow.F)
    ply = A.file_roundtrip(cow, format="ply")
    np.testing.assert_array_equal(ply.V, f.V)
    stl = A.file_roundtrip(cow, format="stl")
    assert stl.n_faces == cow.n_faces
    assert M.surface_distance(cow, stl, n_samples=2000)["hausdorff_rel"] < 1e-6


# --- registry, CLI and bad input ----------------------------------------------------------------------

def test_attack_registry(cow):
    out = A.attack(cow, name="noise", strength=0.001, seed=4)
    np.testing.assert_array_equal(out.V, A.noise(cow, strength=0.001, seed=4).V)
    with pytest.raises(MeshError, match="unknown attack 'blur'"):
        A.attack(cow, name="blur")
    with pytest.raises(MeshError, match="does not take bits"):
        A.attack(cow, name="noise", strength=0.1, bits=3)


@pytest.mark.parametrize("call, match", [
    (lambda: A.noise(TET_V, TET_F, strength=-0.001), "strength must be >= 0"),
    (lambda: A.noise(TET_V, TET_F, strength=0.01, kind="pink"), "unknown noise kind"),
    (lambda: A.simplify(TET_V, TET_F, fraction=1.5), r"fraction .* must be in \(0, 1\]"),
    (lambda: A.simplify(TET_V, TET_F, fraction=0.0), r"must be in \(0, 1\]"),
    (lambda: A.simplify(TET_V, TET_F, fraction=0.5), "too small to simplify"),
    (lambda: A.crop(TET_V, TET_F, fraction=1.0), r"crop fraction must be in \[0, 1\)"),
    (lambda: A.crop(TET_V, TET_F, fraction=-0.1), r"crop fraction must be in \[0, 1\)"),
    (lambda: A.quantize(TET_V, TET_F, bits=0), "bits must be 1..52"),
    (lambda: A.smooth(TET_V, TET_F, iterations=-1), "iterations must be an integer >= 0"),
    (lambda: A.smooth(TET_V, TET_F, lam=float("nan")), "lambda must be finite"),
    (lambda: A.scale(TET_V, TET_F, factor=0), "scale factor must be > 0"),
    (lambda: A.rotate(TET_V, TET_F, axis=(0, 0, 0)), "axis must be a finite non-zero"),
    (lambda: A.noise(TET_V, TET_F, strength=0.01, seed=-1), "seed must be in"),
    (lambda: A.dither_bits(TET_V, 33, np.zeros((4, 3), np.uint64)), r"outside 0..32"),
    (lambda: A.file_roundtrip(TET_V, TET_F, format="gltf"), "unknown round-trip format"),
])
def test_bad_input_is_a_clear_mesh_error(call, match):
    with pytest.raises(MeshError, match=match):
        call()


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "meshmark.cli", *map(str, args)], capture_output=True, text=True)


@pytest.mark.parametrize("args", [
    ["--type", "noise", "--strength", "0.0025"],
    ["--type", "smooth", "--lambda", "0.02", "--iterations", "30"],
    ["--type", "quantize", "--bits", "9"],
    ["--type", "simplify", "--fraction", "0.5"],
    ["--type", "similarity", "--seed", "4"],
    ["--type", "reorder", "--seed", "4"],
    ["--type", "crop", "--fraction", "0.1"],
])
def test_cli_attack(tmp_path, args):
    import json
    src = shared_mesh("classic/cow.obj")
    out = tmp_path / "out.ply"
    r = _cli("attack", src, out, *args, "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    m = meshmark.read_mesh(out)
    assert d["n_vertices"] == m.n_vertices and d["n_faces"] == m.n_faces
    c = _cli("compare", src, out, "--json")
    assert c.returncode == 0, c.stderr
    cd = json.loads(c.stdout)
    for k in ("rmse", "hausdorff", "hausdorff_rel", "normal_deg_mean"):
        assert k in cd
    _check_attack_independently(meshmark.read_mesh(src), m, args, d["distortion"])


def _check_attack_independently(a, b, args, dist):
    """Each attack's effect recomputed with numpy/scipy from its definition (issue 26: the CLI's
    figures must follow the attack's strength, not merely be >= 0). PLY output is float32-exact
    at worst, hence the 1e-6 of the diagonal."""
    from scipy.linalg import orthogonal_procrustes
    from scipy.sparse import coo_matrix
    kind, diag = args[1], float(np.linalg.norm(a.V.max(0) - a.V.min(0)))
    tol = 1e-6 * diag
    D = b.V - a.V if b.n_vertices == a.n_vertices else None
    if kind == "noise":  # eq. 6.3.12: U[-A, A] * d-bar per coordinate, RMS per coordinate A d-bar / sqrt(3)
        A = float(args[3]) * np.linalg.norm(a.V - a.V.mean(0), axis=1).mean()
        assert np.abs(D).max() <= A + tol
        assert abs(np.sqrt((D ** 2).mean()) / (A / np.sqrt(3)) - 1) < 0.03  # ~6 sd over 8,709 draws
        assert dist["rmse"] == pytest.approx(np.sqrt((D ** 2).sum(1).mean()), rel=1e-4)
    elif kind == "quantize":  # at most half a step of 2^bits levels per axis
        step = (a.V.max(0) - a.V.min(0)) / 2 ** int(args[3])
        assert (np.abs(D) <= step / 2 + tol).all() and np.abs(D).max() > 0.4 * step.min()
        assert dist["rmse"] == pytest.approx(np.sqrt((D ** 2).sum(1).mean()), rel=1e-4)
    elif kind == "smooth":  # v += lam (mean of edge neighbours - v), simultaneous steps
        F = a.F
        i, j = np.r_[F[:, 0], F[:, 1], F[:, 2]], np.r_[F[:, 1], F[:, 2], F[:, 0]]
        W = coo_matrix((np.ones(2 * len(i)), (np.r_[i, j], np.r_[j, i])), shape=(a.n_vertices,) * 2).tocsr()
        W.data[:] = 1.0
        W = W.multiply(1.0 / np.asarray(W.sum(1))).tocsr()
        V = a.V.copy()
        for _ in range(int(args[5])):
            V = V + float(args[3]) * (W @ V - V)
        assert np.abs(b.V - V).max() < tol and np.abs(D).max() > 100 * tol
    elif kind == "simplify":
        assert abs(b.n_faces - round(float(args[3]) * a.n_faces)) <= 2 and dist["hausdorff_rel"] < 0.02
    elif kind == "similarity":  # an orthogonal map with uniform scale, fitted by scipy on the same vertex order
        P, Q = a.V - a.V.mean(0), b.V - b.V.mean(0)
        R, ssum = orthogonal_procrustes(P, Q)
        s = ssum / (P ** 2).sum()
        assert np.abs(s * P @ R - Q).max() < 1e-6 * s * diag and dist["hausdorff_rel"] > 1e-3
    elif kind == "reorder":  # the same vertex set and the same surface
        assert np.array_equal(np.unique(a.V.astype(np.float32), axis=0), np.unique(b.V.astype(np.float32), axis=0))
        assert dist["hausdorff_rel"] < 1e-12 and b.n_faces == a.n_faces
    elif kind == "crop":  # faces with every corner at s <= max(s) - f (max(s) - min(s)) along +x
        x = a.V[:, 0]
        keep = (x[a.F] <= x.max() - float(args[3]) * (x.max() - x.min())).all(1)
        assert b.n_faces == keep.sum() and b.n_vertices == len(np.unique(a.F[keep]))
        assert b.V[:, 0].max() <= x.max() - float(args[3]) * (x.max() - x.min()) + tol
    else:
        raise AssertionError(kind)


def test_cli_attack_is_seeded(tmp_path):
    src = shared_mesh("classic/cow.obj")
    for name in ("a", "b"):
        assert _cli("attack", src, tmp_path / f"{name}.ply", "--type", "noise", "--strength", "0.001",
                    "--seed", "5").returncode == 0
    np.testing.assert_array_equal(meshmark.read_mesh(tmp_path / "a.ply").V, meshmark.read_mesh(tmp_path / "b.ply").V)


@pytest.mark.parametrize("args, match", [
    (["--type", "noise", "--strength", "-0.1"], "--strength: strength must be in [0, inf)"),
    (["--type", "crop", "--fraction", "1.5"], "--fraction: fraction must be in [0, 1)"),
    (["--type", "simplify", "--fraction", "2"], "fraction"),
    (["--type", "sharpen"], "unknown attack type 'sharpen'"),
    (["--type", "noise", "--strength", "0.1", "--bits", "3"], "does not take --bits"),
])
def test_cli_attack_errors(tmp_path, args, match):
    r = _cli("attack", shared_mesh("classic/cow.obj"), tmp_path / "o.ply", *args)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert match in r.stderr, r.stderr


def test_cli_simplify_too_small(tmp_path):
    p = tmp_path / "tet.obj"
    meshmark.write_mesh(p, TET_V, TET_F)
    r = _cli("attack", p, tmp_path / "o.obj", "--type", "simplify", "--fraction", "0.5")
    assert r.returncode == 2 and "too small to simplify" in r.stderr
