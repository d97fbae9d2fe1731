"""A keyed random code for short payloads (1-24 data bits), decoded by maximum likelihood over every word.

Each of the 2^k data words w gets its own pseudo-random codeword of n = min(C, 256) bits::

    c_w = AES-256-CTR(K', nonce 0) keystream bytes [w * nb, (w + 1) * nb), nb = ceil(n / 8)
    K'  = HMAC-SHA256(key, "meshmark/v2/<method>/code/<kind>/<k>/<n>")

and the C carriers take code bit ``i mod n`` (cyclic repetition, combined softly). There are no check
bits: the codebook itself is the secret.

**Decoding.** The carriers' signed reliabilities are summed per code bit (``acc``), quantized to
integer weights ``a_i = round(8 |acc_i| / max |acc|)`` with hard bits ``h_i = [acc_i > 0]``, and every
word's weighted disagreement ``D_w = sum_i a_i [c_w,i != h_i]`` is computed (all 2^k words, natively:
``_core.codebook_disagreement``, one table lookup per codeword byte). The word with the smallest D is accepted only if

    (2^k - 1) * P(D_random <= D_min) <= 1e-6,     D_random = sum_i a_i B_i,  B_i ~ Bernoulli(1/2) i.i.d.

and no other word ties with it. ``P(D_random <= d)`` is computed exactly (a convolution of eight
scaled binomials, one per weight level).

**Why a wrong message is rarer than 1e-6 per attempt, whatever the noise.** The noise (an attack, a
deformation, a random mesh) does not know the key, and the codewords of the words other than the
embedded one are AES outputs independent of the embedded codeword, so conditioned on the received
reliabilities each wrong codeword is uniform on {0,1}^n. The threshold depends on the weights only, so
by the union bound P(some wrong word passes) <= (2^k - 1) P(D_random <= threshold) <= 1e-6. With hard
decisions (all weights equal) this is the Hamming ball: e.g. k = 16, n = 108 accepts up to 20
disagreements (99.8 % of frames at 10 % flips).

Against the tail-biting convolutional code with a 20-bit keyed check (:mod:`.coding`) it spends no
bits on a check, so at the same carriers it decodes more frames; docs/coding.md has the measured curve.
Decoding costs about 1 ms at k = 16 and 30 ms at k = 20 (the codebook, 2^k * nb bytes, at most
32 MB, is cached: at most 64 MB of codebooks, least recently used dropped first); from 21 to 24 bits the
codebook is streamed in blocks of 2^20 words and never held whole (about 0.3 s at 24 bits).
"""
from __future__ import annotations

import hashlib
import hmac
from collections import OrderedDict

import numpy as np

from .. import _core
from .._core import MeshError

MAX_DATA_BITS = 24
CACHED_DATA_BITS = 20  # codebooks up to 2^20 words are built whole and cached; longer ones are streamed
CHUNK_WORDS = 1 << 20  # words per streamed block
MAX_CODE_BITS = 256
LEVELS = 8
ALPHA = 1e-6


def code_bits(n_carriers: int) -> int:
    """Length n of the codewords for ``n_carriers`` carriers."""
    return int(min(int(n_carriers), MAX_CODE_BITS))


def _check(k: int, n: int) -> None:
    if not 1 <= int(k) <= MAX_DATA_BITS or not 1 <= int(n) <= MAX_CODE_BITS:
        raise MeshError(f"the keyed code takes 1..{MAX_DATA_BITS} data bits and 1..{MAX_CODE_BITS} code bits, "
                        f"got {k} and {n}")


def _keystream(key: str, method: str, kind: str, k: int, n: int, first: int, count: int) -> np.ndarray:
    """(count, nb) uint8: the packed codewords of words first .. first + count - 1. The codebook is one
    AES-256-CTR keystream (counter block 0 first); a block of it starts at counter (first nb) // 16."""
    from cryptography.hazmat.primitives.ciphers import Cipher, algorithms, modes
    nb = (n + 7) // 8
    kk = hmac.new(key.encode("utf-8"), f"meshmark/v2/{method}/code/{kind}/{k}/{n}".encode(), hashlib.sha256).digest()
    start = first * nb
    skip = start % 16
    enc = Cipher(algorithms.AES(kk), modes.CTR((start // 16).to_bytes(16, "big"))).encryptor()
    raw = enc.update(bytes(skip + count * nb)) + enc.finalize()
    book = np.frombuffer(raw, np.uint8)[skip:].reshape(count, nb).copy()
    if n % 8:
        book[:, -1] &= np.uint8((0xFF << (8 - n % 8)) & 0xFF)  # bits beyond n are zero (never compared)
    return book


_CACHE: "OrderedDict[tuple, np.ndarray]" = OrderedDict()
CACHE_BYTES = 64 << 20  # codebooks kept in memory (least recently used dropped first)


def _codebook(key: str, method: str, kind: str, k: int, n: int) -> np.ndarray:
    ident = (key, method, kind, k, n)
    book = _CACHE.get(ident)
    if book is None:
        book = _keystream(key, method, kind, k, n, 0, 1 << k)
        book.setflags(write=False)
        _CACHE[ident] = book
        while len(_CACHE) > 1 and sum(b.nbytes for b in _CACHE.values()) > CACHE_BYTES:
            _CACHE.popitem(last=False)
    _CACHE.move_to_end(ident)
    return book


def codebook(key: str, method: str, kind: str, k: int, n: int) -> np.ndarray:
    """(2^k, ceil(n/8)) uint8: every data word's packed codeword (MSB first), word index = the data bits
    read as a big-endian integer. Cached; for k <= CACHED_DATA_BITS (longer codebooks are streamed)."""
    _check(k, n)
    if int(k) > CACHED_DATA_BITS:
        raise MeshError(f"a codebook of 2^{k} words is not built whole (at most 2^{CACHED_DATA_BITS})")
    return _codebook(str(key), str(method), str(kind), int(k), int(n))


def _word(data: np.ndarray) -> int:
    data = np.asarray(data, np.int64)
    return int((data << np.arange(data.size - 1, -1, -1)).sum())


def encode(data: np.ndarray, kind: str, key: str, method: str, C: int) -> np.ndarray:
    """(C,) coded bits (0/1) carrying the k data bits: carrier i takes code bit i mod n."""
    data = np.asarray(data, np.uint8)
    n = code_bits(C)
    _check(data.size, n)
    c = np.unpackbits(_keystream(str(key), str(method), str(kind), data.size, n, _word(data), 1)[0])[:n]
    return c[np.arange(int(C)) % n]


def _half_binomial(m: int) -> np.ndarray:
    """(m + 1,) pmf of Bin(m, 1/2), from the log-ratios of consecutive terms (no scipy: Blender's Python)."""
    j = np.arange(1, m + 1, dtype=np.float64)
    logp = np.concatenate([[0.0], np.cumsum(np.log((m - j + 1) / j))]) - m * np.log(2.0)
    return np.exp(logp)


def tail(weights: np.ndarray) -> np.ndarray:
    """cdf[d] = P(sum_i a_i B_i <= d), B_i ~ Bernoulli(1/2) independent, for integer weights 0..LEVELS."""
    a = np.asarray(weights, np.int64)
    counts = np.bincount(a, minlength=LEVELS + 1)
    pmf = np.ones(1)
    for v in range(1, LEVELS + 1):  # one convolution per weight level (8), not per bit
        m = int(counts[v])
        if m:
            d = np.zeros(v * m + 1)
            d[::v] = _half_binomial(m)
            pmf = np.convolve(pmf, d)
    return np.cumsum(pmf)


def threshold(weights: np.ndarray, k: int, alpha: float = ALPHA) -> int:
    """Largest disagreement d with (2^k - 1) P(D_random <= d) <= alpha (-1 if none)."""
    ok = np.flatnonzero(((1 << int(k)) - 1) * tail(weights) <= alpha)
    return int(ok[-1]) if ok.size else -1


def _weights(llr: np.ndarray):
    """(n, weights, packed hard bits): the reliabilities summed per code bit and quantized."""
    llr = np.asarray(llr, np.float64)
    n = code_bits(llr.size)
    acc = np.bincount(np.arange(llr.size) % n, weights=llr, minlength=n)
    mx = float(np.abs(acc).max()) if acc.size else 0.0
    a = np.rint(LEVELS * np.abs(acc) / mx).astype(np.int64) if mx > 0 else np.zeros(n, np.int64)
    return n, a, np.packbits((acc > 0).astype(np.uint8))


def _padded(a: np.ndarray, nb: int) -> np.ndarray:
    apad = np.zeros(nb * 8, np.int32)
    apad[:a.size] = a
    return apad


def scores(llr: np.ndarray, k: int, kind: str, key: str, method: str):
    """(D, weights): every word's weighted disagreement with the received word, and the weights
    (k <= CACHED_DATA_BITS)."""
    n, a, h = _weights(llr)
    book = codebook(key, method, kind, k, n)
    return np.asarray(_core.codebook_disagreement(book, h, _padded(a, book.shape[1])), np.int64), a


def _search(llr: np.ndarray, k: int, kind: str, key: str, method: str):
    """(best word, its disagreement, how many words share it, weights): over all 2^k words, the codebook
    cached (k <= CACHED_DATA_BITS) or streamed in blocks of CHUNK_WORDS (2^24 words: about 0.3 s)."""
    if k <= CACHED_DATA_BITS:
        D, a = scores(llr, k, kind, key, method)
        w = int(np.argmin(D))
        return w, int(D[w]), int((D == D[w]).sum()), a
    n, a, h = _weights(llr)
    nb = (n + 7) // 8
    apad = _padded(a, nb)
    best, dmin, ties = -1, None, 0
    for first in range(0, 1 << k, CHUNK_WORDS):  # blocks of a million words, not elements
        count = min(CHUNK_WORDS, (1 << k) - first)
        D = np.asarray(_core.codebook_disagreement(_keystream(key, method, kind, k, n, first, count), h, apad))
        j = int(np.argmin(D))
        d = int(D[j])
        if dmin is None or d < dmin:
            best, dmin, ties = first + j, d, int((D == d).sum())
        elif d == dmin:
            ties += int((D == d).sum())
    return best, dmin, ties, a


def decode(llr: np.ndarray, k: int, kind: str, key: str, method: str, alpha: float = ALPHA):
    """(data bits or None, reason): the maximum-likelihood word if it passes the threshold (a wrong word
    passes with probability <= ``alpha``, 1e-6, per attempt)."""
    _check(k, code_bits(np.asarray(llr).size))
    w, dmin, ties, a = _search(llr, k, kind, key, method)
    tau = threshold(a, k, alpha)
    if dmin > tau:
        return None, (f"no codeword is close enough to be accepted (best {dmin} against at most {tau} weighted "
                      "disagreements: too many carrier errors to decode the message)")
    if ties > 1:
        return None, "two codewords are equally close (the message cannot be decided)"
    return ((w >> np.arange(k - 1, -1, -1)) & 1).astype(np.uint8), ""
