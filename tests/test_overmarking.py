"""Overmarking (issue 11, docs/security.md §5): with the same bins a second embedding with another
key erases the owner's mark; with key-dependent bin placement (key_bins=True) the owner's radial mark
survives it (examples/overmarking.py measures all methods on Bunny, Horse and Hand)."""
import pytest

import meshmark
import meshmark.watermark as W
from meshmark import MeshError
from meshmark.watermark.keys import key_bins

from conftest import shared_mesh


def test_key_bins_moves_K_by_3_to_12_percent():
    Ks = [key_bins(f"k{i}", "radial", 400) for i in range(200)]
    assert all(12 <= abs(k - 400) <= 48 for k in Ks)  # round(400 * [0.03, 0.12])
    assert min(Ks) < 400 < max(Ks) and len(set(Ks)) > 30
    assert key_bins("k1", "radial", 400) == key_bins("k1", "radial", 400) != key_bins("k1", "cho-mean", 400)
    assert key_bins("x", "cho-mean", 4) >= 4


def test_overmarking_with_and_without_key_bins():
    m = meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
    bits, other = [1, 0, 1, 1, 0], [0, 1, 0, 0, 1]
    plain = W.embed(m, payload=bits, key="owner-key-A", method="radial")
    over = W.embed(m.with_vertices(plain.V), payload=other, key="attacker-key-0", method="radial")
    x = W.extract(m.with_vertices(over.V), keyfile=plain.keyfile)
    assert not x.detected and 0.4 < x.cdr < 0.6  # the same 400 bins: every bin rewritten
    own = W.embed(m, payload=bits, key="owner-key-A", method="radial", key_bins=True)
    assert own.keyfile.params["K"] == key_bins("owner-key-A", "radial", 400) != 400
    over = W.embed(m.with_vertices(own.V), payload=other, key="attacker-key-0", method="radial")
    x = W.extract(m.with_vertices(over.V), keyfile=own.keyfile)
    assert x.detected and x.cdr > 0.7 and x.message == "10110"
    with pytest.raises(MeshError, match="key_bins chooses the bin count K from the key: do not give K"):
        W.embed(m, payload=bits, key="k", method="radial", key_bins=True, K=400)
