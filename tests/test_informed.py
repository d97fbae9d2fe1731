"""Informed tracing (meshmark.watermark.informed): derived null, alignment, resampling, a few attacks."""
import math
import os

import numpy as np
import pytest
from scipy import stats
from scipy.spatial import cKDTree

import meshmark
from meshmark import _core, attacks
from meshmark.watermark import informed, tracing

from conftest import shared_mesh


@pytest.fixture(scope="module")
def cat():
    return meshmark.weld_vertices(meshmark.read_mesh(shared_mesh("corpus/odedstein_cat-low-resolution.obj"))).mesh


def test_keyed_gaussians_are_standard_normal():
    W = _core.keyed_gaussians([1, 2, 3], 20000)
    assert W.shape == (20000, 3)
    for j in range(3):
        assert stats.kstest(W[:, j], "norm").pvalue > 1e-3
    assert abs(np.corrcoef(W.T)[0, 1]) < 0.05
    u = np.random.default_rng(0).normal(size=20000)
    assert np.allclose(_core.keyed_gaussian_dots(u, [1, 2, 3]), u @ W)


def test_derived_null_by_monte_carlo(cat):
    """z of fields not in the suspect is N(0,1) whatever the residual: 2,000 fields correlated with the
    residual of a heavily attacked copy; the tail at z = 3 and a KS test against N(0,1)."""
    orig = informed.Original(cat, informed.default_params(cat))
    sus = attacks.noise(attacks.smooth(cat.with_vertices(orig.marked(orig.patterns([7])[:, 0])), iterations=30),
                        strength=0.0025, seed=1)
    seeds = list(range(1000, 3000))
    det = informed.detect(sus, orig, [7] + seeds)
    z = det["z"]
    assert z[0] > 6  # the copy present
    zn = z[1:]
    assert stats.kstest(zn, "norm").pvalue > 1e-3
    assert abs(zn.mean()) < 0.1 and abs(zn.std() - 1) < 0.06
    assert np.mean(zn > 3) < 5 * stats.norm.sf(3)


def test_alignment_recovers_similarity_and_crop(cat):
    orig = informed.Original(cat, informed.default_params(cat))
    cropped = attacks.crop(cat, fraction=0.3, normal=(0, 1, 0))
    R = attacks.random_rotation(5)
    s, t = 1.7, np.array([0.3, -2.0, 5.0])
    sus = meshmark.Mesh.from_polygons(s * cropped.V @ R.T + t, cropped.face_indices, cropped.face_offsets)
    al = informed.align(sus, orig)
    A = al["matrix"]
    back = sus.V @ A[:3, :3].T + A[:3, 3]
    err = np.linalg.norm(back - cropped.V, axis=1).max() / orig.diag
    assert err < 1e-6
    assert math.isclose(np.cbrt(np.linalg.det(A[:3, :3])), 1 / s, rel_tol=1e-6)


def test_closest_points_match_ckdtree_on_vertices_and_are_exact(cat):
    T = np.ascontiguousarray(informed._tri(cat), np.int32)
    rng = np.random.default_rng(0)
    P = cat.V[rng.choice(cat.n_vertices, 500, replace=False)] + rng.normal(scale=1e-3, size=(500, 3))
    Q, face, bary, d2 = _core.closest_points(P, cat.V, T)
    # barycentric weights reproduce the point
    assert np.allclose((bary[:, :, None] * cat.V[T[face]]).sum(1), Q, atol=1e-12)
    # never farther than the nearest vertex (cKDTree), and within the surface's reach of it
    dv, _ = cKDTree(cat.V).query(P)
    assert np.all(np.sqrt(d2) <= dv + 1e-12)
    assert np.allclose(np.sqrt(d2), _core.point_mesh_distance(P, cat.V, T)[0], atol=1e-12)


def test_a_tree_built_once_gives_the_same_closest_points_and_alignment(cat):
    T = np.ascontiguousarray(informed._tri(cat), np.int32)
    tree = _core.TriangleTree(cat.V, T)
    assert tree.size == len(T)
    rng = np.random.default_rng(1)
    P = np.ascontiguousarray(cat.V[rng.choice(cat.n_vertices, 300, replace=False)] * 1.1 + 0.01)
    for a, b in zip(_core.closest_points(P, cat.V, T), _core.closest_points(P, tree)):
        assert np.array_equal(a, b)
    shifted = np.eye(4)
    shifted[:3, :3] = informed.proper_axis_rotations()[1]
    starts = [np.eye(4), shifted]
    r1 = _core.align_similarity(P, cat.V, T, starts, 3, 5, 0.5, True, top=2, refine=4)
    r2 = _core.align_similarity(P, tree, starts, 3, 5, 0.5, True, top=2, refine=4)
    assert np.array_equal(r1[0], r2[0]) and r1[1:] == r2[1:]


def _issue(tmp_path, mesh, n=8):
    reg = os.path.join(tmp_path, "r.sqlite")
    return reg, tracing.issue(mesh, key="k", registry=reg, n_copies=n)


@pytest.mark.parametrize("attack", ["noise", "simplify", "crop"])
def test_attacked_copy_traced_with_original_only(tmp_path, cat, attack):
    reg, copies = _issue(tmp_path, cat)
    cid, V = copies[3]
    m = cat.with_vertices(V)
    sus = {"noise": lambda: attacks.noise(m, strength=0.0025, seed=2),
           "simplify": lambda: attacks.simplify(m, fraction=0.25),
           "crop": lambda: attacks.crop(m, fraction=0.3, normal=(0, 1, 0))}[attack]()
    sus = attacks.reorder(attacks.similarity(sus, seed=4), seed=4)
    r = tracing.trace(sus, registry=reg, original=cat)
    assert r["evidence"] == "informed+blind"
    assert r["copy"] == cid and r["informed"]["copy"] == cid
    assert r["informed"]["z"] > 5.73
    blind = tracing.trace(sus, registry=reg)
    assert blind["evidence"] == "blind" and blind["informed"] is None
    unmarked = tracing.trace(attacks.noise(cat, strength=0.0025, seed=2), registry=reg, original=cat)
    assert unmarked["copy"] is None


def test_original_found_at_recorded_path_and_digest_checked(tmp_path, cat):
    src = os.path.join(tmp_path, "cat.obj")
    meshmark.write_mesh(src, cat)
    orig = meshmark.read_mesh(src)
    reg = os.path.join(tmp_path, "r.sqlite")
    (cid, V), = tracing.issue(orig, key="k", registry=reg, n_copies=1, original=src)
    sus = attacks.noise(orig.with_vertices(V), strength=0.001, seed=0)
    r = tracing.trace(sus, registry=reg)
    assert r["evidence"] == "informed+blind" and r["originals"][0]["status"] == "recorded"
    os.remove(src)
    meshmark.write_mesh(src, attacks.noise(orig, strength=0.001, seed=9))
    r = tracing.trace(sus, registry=reg)
    assert r["evidence"] == "blind" and r["originals"][0]["status"] == "digest mismatch"
    with pytest.raises(meshmark.MeshError, match="not the original"):
        tracing.trace(sus, registry=reg, original=attacks.noise(orig, strength=0.001, seed=9))


def test_evaluation_quick_mode(tmp_path):
    """examples/informed_tracing.py --quick: the cat, 10 copies, 3 attacks, false-alarm trials."""
    import csv
    import sys

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
    import informed_tracing

    assert informed_tracing.main(["--quick", "--out", str(tmp_path)]) == 0
    rows = list(csv.DictReader(open(tmp_path / "trials.csv")))
    copies = [r for r in rows if r["kind"] == "copy"]
    assert len(copies) == 3 and all(r["named"] == r["truth"] for r in copies)
    assert all(r["named"] == "" for r in rows if r["kind"] != "copy")
