"""The Chao et al. 2009 baseline (meshmark.stego.chao) as thesis §8.2 runs it: 10 layers, 10000 intervals."""
import numpy as np
import pytest

import meshmark
from meshmark import MeshError
from meshmark.stego import chao
from conftest import shared_mesh


@pytest.fixture(scope="module")
def bunny():
    return meshmark.read_mesh(shared_mesh("classic/bunny.obj"))


def test_capacity_and_exact_extraction(bunny):
    res = chao.embed(bunny, message=b"", fill=True, seed=3)
    n_fixed = len({*res.frame["ia"].tolist(), *res.frame["ib"].tolist()})
    assert res.capacity_bits == 3 * 10 * (bunny.n_vertices - n_fixed)  # Table 7.4: 3 n_layers |v|
    assert 29.9 < res.bits_per_vertex <= 30.0
    bits = np.random.default_rng(3).integers(0, 2, res.capacity_bits)
    got = chao.extract(bunny.with_vertices(res.V), res.capacity_bits, frame=res.frame)
    assert np.array_equal(got, bits)


def test_geometry_of_the_moves(bunny):
    res = chao.embed(bunny, message=b"", fill=True, seed=4)
    f = res.frame
    Q, c = f["axes"], f["centroid"]
    P0, P1 = (bunny.V - c) @ Q, (res.V - c) @ Q
    # the extreme vertices V_a, V_b do not move; nobody leaves [pa, pb]
    fixed = np.unique(np.concatenate([f["ia"], f["ib"]]))
    assert np.array_equal(res.V[fixed], bunny.V[fixed])
    assert (P1 >= f["pa"] - 1e-12).all() and (P1 <= f["pb"] + 1e-12).all()
    # a move along one axis stays within one layer-1 interval (mirror into the neighbour) plus the
    # edge intervals' detour
    ell = (f["pb"] - f["pa"]) / 10000
    assert (np.abs(P1 - P0) <= 2 * ell + 1e-12).all()
    # the layer bits are the interval parities of the new positions
    d = (P1 - f["pa"]) / ell
    k = np.minimum(np.floor(d), 9999).astype(np.int64)
    got = chao.extract(bunny.with_vertices(res.V), res.capacity_bits, frame=f).reshape(-1, 3, 10)
    carriers = np.setdiff1d(np.arange(bunny.n_vertices), fixed)
    assert np.array_equal(got[:, :, 0], (k[carriers] & 1))


def test_blind_mode_recomputes_the_frame(bunny):
    """The paper's blind extraction recomputes PCA from the marked mesh: the coarse layers survive
    the small change of the axes, the fine ones do not (measured, docs/stego.md)."""
    res = chao.embed(bunny, message=b"", fill=True, seed=5)
    bits = np.random.default_rng(5).integers(0, 2, res.capacity_bits)
    got = chao.extract(bunny.with_vertices(res.V), res.capacity_bits)
    ber = (got != bits).reshape(-1, 3, 10).mean(axis=(0, 1))
    assert ber[0] < 0.05 and ber[-1] > 0.3


def test_bad_input(bunny):
    with pytest.raises(MeshError, match="exceeds"):
        chao.embed(bunny, bits=np.ones(31 * bunny.n_vertices, np.uint8))
    with pytest.raises(MeshError, match="exactly one"):
        chao.embed(bunny)
    with pytest.raises(MeshError, match="n_layers"):
        chao.embed(bunny, message=b"x", n_layers=0)
