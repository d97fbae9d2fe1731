"""The keyed random code (watermark/keyed_code.py, docs/coding.md §1): the exact tail against brute
force and the binomial, the acceptance threshold against the analytic Hamming-ball count, the wrong-word
rate against Monte Carlo, the native search against a plain count, and the framework writing and still
reading both schemes."""
import itertools
import math

import numpy as np
import pytest
from scipy.stats import binom

from meshmark import MeshError
from meshmark.watermark import coding, keyed_code as kc


def test_tail_equals_brute_force_and_binomial():
    rng = np.random.default_rng(1)
    a = rng.integers(0, kc.LEVELS + 1, 12)
    sums = np.array([np.dot(a, b) for b in itertools.product([0, 1], repeat=a.size)])
    ref = np.array([(sums <= d).mean() for d in range(a.sum() + 1)])
    assert np.allclose(kc.tail(a), ref, rtol=1e-12, atol=0)
    eq = np.full(108, kc.LEVELS)  # hard decisions: D = 8 * Hamming distance
    t = kc.tail(eq)
    assert np.allclose(t[:: kc.LEVELS], binom.cdf(np.arange(109), 108, 0.5), rtol=1e-10, atol=0)
    assert t[-1] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("n,k,t", [(108, 16, 20), (102, 16, 18), (54, 16, 3), (84, 8, 15)])
def test_hard_threshold_is_the_hamming_ball_of_the_union_bound(n, k, t):
    """With equal weights the largest accepted distance t satisfies (2^k - 1) V(n, t) / 2^n <= 1e-6 <
    (2^k - 1) V(n, t + 1) / 2^n, V the Hamming-ball volume (exact integers)."""
    vol = lambda r: sum(math.comb(n, i) for i in range(r + 1))  # noqa: E731
    assert ((1 << k) - 1) * vol(t) <= 1e-6 * 2 ** n < ((1 << k) - 1) * vol(t + 1)
    assert kc.threshold(np.full(n, kc.LEVELS), k) == kc.LEVELS * t + kc.LEVELS - 1  # any D < 8 (t + 1)


def test_wrong_word_rate_matches_its_bound_by_monte_carlo():
    """Pure noise (a wrong key's or an unmarked mesh's reliabilities) at alpha = 0.05 instead of 1e-6:
    the acceptance rate stays below alpha and near it (the union bound is tight for a random code)."""
    rng = np.random.default_rng(2)
    trials, hits = 2000, 0
    for i in range(trials):
        hits += kc.decode(rng.normal(size=60), 8, "bits", f"noise{i % 50}", "laplacian", alpha=0.05)[0] is not None
    rate = hits / trials
    assert rate <= 0.05 + 3 * math.sqrt(0.05 * 0.95 / trials)
    assert rate >= 0.02, rate  # measured 0.0375: the threshold is not needlessly strict


def test_scores_equal_a_plain_count():
    rng = np.random.default_rng(3)
    k, C = 10, 77
    llr = rng.normal(size=C)
    D, a = kc.scores(llr, k, "text", "key", "radial")
    book = np.unpackbits(kc.codebook("key", "radial", "text", k, C), axis=1)[:, :C].astype(bool)
    acc = llr  # C <= 256: one carrier per code bit
    assert np.array_equal(a, np.rint(8 * np.abs(acc) / np.abs(acc).max()))
    ref = ((book != (acc > 0)) * a).sum(axis=1)
    assert np.array_equal(D, ref)


def test_codebook_is_keyed_balanced_and_repeats_cyclically():
    b1 = kc.codebook("k1", "laplacian", "bits", 16, 108)
    assert b1.shape == (1 << 16, 14) and np.array_equal(b1, kc.codebook("k1", "laplacian", "bits", 16, 108))
    for other in (("k2", "laplacian", "bits", 16, 108), ("k1", "radial", "bits", 16, 108),
                  ("k1", "laplacian", "text", 16, 108), ("k1", "laplacian", "bits", 16, 109)):
        assert (kc.codebook(*other)[:, :13] != b1[:, :13]).mean() > 0.99
    bits = np.unpackbits(b1, axis=1)[:, :108]
    assert abs(bits.mean() - 0.5) < 0.002 and not np.any(np.unpackbits(b1[:, -1:], axis=1)[:, 4:])
    data = np.unpackbits(np.frombuffer(b"Hi", np.uint8))
    c = kc.encode(data, "text", "k", "laplacian", 600)  # n = 256, repeated
    assert c.size == 600 and np.array_equal(c[:256], c[256:512]) and np.array_equal(c[512:], c[:88])
    got, reason = coding.decode(2.0 * c - 1, 16, "text", "k", "laplacian")
    assert reason == "" and np.array_equal(got, data)
    assert coding.decode(2.0 * c - 1, 16, "text", "k-wrong", "laplacian")[0] is None


def test_schemes_by_payload_length():
    assert coding.scheme_for(1) == coding.scheme_for(24) == coding.KEYED
    assert coding.scheme_for(25) == coding.scheme_for(32) == coding.TBCC9
    assert coding.coding_field(8, 60) == {"scheme": coding.KEYED, "info_bits": 8, "check_bits": 0, "n_coded": 60}


def test_framework_writes_the_keyed_code_and_still_reads_tbcc_keyfiles(monkeypatch):
    """A 1-byte text is coded with the keyed code; a keyfile written with the convolutional code for the
    same payload (every keyfile before this scheme) still decodes, through the scheme it names."""
    import meshmark.watermark as W
    from meshmark.shapes import default_mesh
    m = default_mesh()
    new = W.embed(m, payload="h", key="owner")
    assert new.keyfile.coding["scheme"] == coding.KEYED and new.keyfile.coding["check_bits"] == 0
    r = W.extract(new.V, m.F, keyfile=new.keyfile)
    assert r.detected and r.message == "h"
    with monkeypatch.context() as mp:
        mp.setattr(coding, "scheme_for", lambda n: coding.TBCC)
        old = W.embed(m, payload="h", key="owner")
    assert old.keyfile.coding == {"scheme": coding.TBCC, "info_bits": 28, "check_bits": 20,
                                  "n_coded": old.keyfile.coding["n_coded"]}
    r = W.extract(old.V, m.F, keyfile=old.keyfile)
    assert r.detected and r.message == "h"
    wrong = W.extract(new.V, m.F, keyfile=new.keyfile, key="not-the-owner")
    assert not wrong.detected and wrong.message is None


def test_half_binomial_is_exact_to_rounding():
    """The pmf without scipy (Blender's Python has none) equals exact integer binomials / 2^m."""
    for m in (1, 7, 108, 256):
        exact = np.array([math.comb(m, j) for j in range(m + 1)], float) / 2.0 ** m
        assert np.allclose(kc._half_binomial(m), exact, rtol=1e-11, atol=0)


def test_streamed_blocks_are_the_codebook_and_search_the_same(monkeypatch):
    """Beyond CACHED_DATA_BITS the codebook is streamed: a block seeked to any word equals that slice
    of the whole keystream (so encoding and decoding agree on every word), and the streamed search
    decides exactly as the whole-codebook search on noisy frames (both paths forced on k = 12)."""
    whole = kc._keystream("k", "laplacian", "bits", 12, 101, 0, 1 << 12)
    for first, count in ((0, 1), (1, 3), (7, 100), (4095, 1), (1000, 3096)):
        assert np.array_equal(kc._keystream("k", "laplacian", "bits", 12, 101, first, count), whole[first:first + count])
    assert np.array_equal(whole, kc.codebook("k", "laplacian", "bits", 12, 101))
    rng = np.random.default_rng(6)
    frames = []
    for i in range(60):  # half lightly, half heavily flipped: both outcomes occur
        data = rng.integers(0, 2, 12).astype(np.uint8)
        p = 0.08 if i < 30 else 0.3
        y = (2.0 * kc.encode(data, "bits", "k", "laplacian", 101) - 1) * np.where(rng.random(101) < p, -1, 1)
        frames.append((data, y * rng.uniform(0.2, 1.0, 101)))
    ref = [kc.decode(y, 12, "bits", "k", "laplacian") for _, y in frames]
    monkeypatch.setattr(kc, "CACHED_DATA_BITS", 8)
    monkeypatch.setattr(kc, "CHUNK_WORDS", 300)  # 14 blocks, the last one short
    got = [kc.decode(y, 12, "bits", "k", "laplacian") for _, y in frames]
    assert all((a[0] is None and b[0] is None) or np.array_equal(a[0], b[0]) for a, b in zip(ref, got))
    right = sum(a[0] is not None and np.array_equal(a[0], d) for a, (d, _) in zip(ref, frames))
    assert 30 <= right < 60, right
    with pytest.raises(MeshError, match="not built whole"):
        kc.codebook("k", "laplacian", "bits", 12, 101)


def test_24_bit_payload_round_trip_and_wrong_key():
    data = np.unpackbits(np.frombuffer(b"Hi!", np.uint8))
    c = coding.encode(data, "text", "k", "laplacian", 140)
    rng = np.random.default_rng(8)
    y = (2.0 * c - 1) * np.where(rng.random(140) < 0.12, -1, 1)
    got, reason = coding.decode(y, 24, "text", "k", "laplacian")
    assert reason == "" and np.array_equal(got, data)
    assert coding.decode(2.0 * c - 1, 24, "text", "other", "laplacian")[0] is None


def test_out_of_range_lengths_are_a_mesh_error():
    with pytest.raises(MeshError, match=r"takes 1..24 data bits and 1..256 code bits, got 25 and 100"):
        kc.encode(np.zeros(25, np.uint8), "bits", "k", "laplacian", 100)
    with pytest.raises(MeshError, match="got 30 and 120"):
        coding.decode(np.ones(120), 30, "bits", "k", "laplacian", coding.KEYED)
