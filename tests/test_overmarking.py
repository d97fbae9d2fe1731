"""Overmarking (issues 11 and 23, docs/security.md §5): with the same bins a second embedding with
another key erases the owner's mark; with key-dependent bin placement (key_bins=True, also with the
automatic parameters) the owner's mark survives it in most cases (examples/overmarking.py measures
the four methods on Bunny, Horse, Hand and Cow)."""
import json
import subprocess
import sys

import pytest

import meshmark
import meshmark.watermark as W
from meshmark import MeshError
from meshmark.watermark.coding import max_data_bits
from meshmark.watermark.keys import key_bins
from meshmark.watermark.payload import Payload

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


def _overmark(m, own, method, attacker_key, key_bins=False):
    att = W.embed(m.with_vertices(own.V), payload=Payload.from_text("LEAK"), key=attacker_key, method=method,
                  key_bins=key_bins)
    return m.with_vertices(att.V), att


def test_key_bins_with_automatic_parameters_survives_overmarking():
    """Issue 23: a 4-byte message with key_bins and automatic parameters (was refused: the thesis K
    was moved), the owner's Cho-mean mark found after a leaker's re-embedding, a wrong key not."""
    m = meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
    own = W.embed(m, payload=Payload.from_text("OWN1"), key="owner-key-A", method="cho-mean", key_bins=True)
    plain = W.embed(m, payload=Payload.from_text("OWN1"), key="owner-key-A", method="cho-mean")
    # auto: 32 + 20 bits need 78 carriers, so the second rung (128 bins), moved by the key to 122
    assert plain.keyfile.params["K"] == plain.capacity == 128
    assert own.keyfile.params["K"] == own.capacity == key_bins("owner-key-A", "cho-mean", 128) == 122
    assert own.keyfile.choice["key_bins"] is True and own.keyfile.choice["rung"] == 1
    over, att = _overmark(m, plain, "cho-mean", "attacker-key-1")
    x = W.extract(over, keyfile=plain.keyfile)
    assert not x.detected and 0.45 < x.cdr < 0.6  # the same 128 bins: the owner's mark erased
    over, att = _overmark(m, own, "cho-mean", "attacker-key-1")  # the leaker: automatic parameters
    assert att.keyfile.params["K"] == 128 and W.extract(over, keyfile=att.keyfile).detected
    x = W.extract(over, keyfile=own.keyfile)
    assert x.detected and x.p_false_alarm < 1e-12 and round(x.cdr, 4) == 0.8279
    assert x.message is None  # detected, but too many bits flipped for the code to give the message back
    wrong = W.extract(over, keyfile=own.keyfile, key="not-the-owner")
    assert not wrong.detected and wrong.p_false_alarm > 0.9
    over, att = _overmark(m, own, "cho-mean", "attacker-key-2", key_bins=True)  # a leaker with key bins
    assert att.keyfile.params["K"] == 142
    x = W.extract(over, keyfile=own.keyfile)
    assert x.detected and round(x.cdr, 4) == 0.8033 and x.message == "OWN1"
    assert not W.extract(over, keyfile=own.keyfile, key="not-the-owner").detected


def test_key_bins_laplacian_auto_cli(tmp_path):
    """The CLI's --key-bins with the default (automatic) parameters on the Laplacian method: the
    first rung's K = ceil(N/70) = 498 moved to 478, and the owner's mark survives one leaker."""
    src = str(shared_mesh("classic/bunny.obj"))
    out, kf = tmp_path / "m.obj", tmp_path / "k.json"
    r = subprocess.run([sys.executable, "-m", "meshmark", "embed", src, str(out), "--message", "OWN1",
                        "--key", "owner-key-A", "--keyfile", str(kf), "--key-bins", "--json"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["params"]["K"] == key_bins("owner-key-A", "laplacian", 498) == 478 and d["params_choice"]["rung"] == 0
    m = meshmark.read_mesh(src)
    own = W.embed(m, payload=Payload.from_text("OWN1"), key="owner-key-A", method="laplacian", key_bins=True)
    assert own.keyfile.params["K"] == 478 and own.capacity == d["capacity"]
    over, att = _overmark(m, own, "laplacian", "attacker-key-0")
    assert att.keyfile.params["K"] == 498
    x = W.extract(over, keyfile=own.keyfile)
    assert x.detected and round(x.cdr, 4) == 0.7426
    assert not W.extract(over, keyfile=own.keyfile, key="not-the-owner").detected


def test_capacity_with_key_bins_is_what_embed_uses(tmp_path):
    """capacity(key_bins=True, key=...) and `meshmark capacity --key-bins --key` report the bins and
    carriers embed --key-bins uses with that key (Cho-variance, auto: 128 bins moved to 143)."""
    m = meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
    r = W.embed(m, payload=Payload.from_text("OWN1"), key="owner-key-A", method="cho-variance", key_bins=True)
    assert r.keyfile.params["K"] == r.capacity == 143
    assert W.capacity(m, method="cho-variance", n_data=32, key="owner-key-A", key_bins=True) == 143
    assert W.capacity(m, method="cho-variance", n_data=32) == 128
    with pytest.raises(MeshError, match="the key must be a non-empty string"):
        W.capacity(m, method="cho-variance", key_bins=True)
    run = lambda *a: subprocess.run([sys.executable, "-m", "meshmark", "capacity", str(shared_mesh("classic/bunny.obj")),
                                     "--method", "cho-variance", "--json", *a], capture_output=True, text=True)
    plain, kb = json.loads(run().stdout), json.loads(run("--key-bins", "--key", "owner-key-A").stdout)
    assert plain["params"]["K"] == plain["capacity"] == 64 and plain["key_bins"] is False  # the first rung
    assert kb["params"]["K"] == kb["capacity"] == key_bins("owner-key-A", "cho-variance", 64) and kb["key_bins"] is True
    assert kb["thesis"] == plain["thesis"]  # the published figures stay the published ones
    assert kb["auto"]["max_message_bits"] == max_data_bits(143) == 75  # the longest: the 128-bin rung, moved
    bad = run("--key-bins")
    assert bad.returncode == 2 and "--key-bins needs --key" in bad.stderr
