"""Keys: a secret string decides which carrier takes which coded bit, and flips (whitens) the bits.

Everything is derived with SHAKE-256 (hashlib), domain-separated by method, so keyfiles stay valid
across numpy versions and platforms:

* the carrier order: ``argsort`` of 64-bit words from ``SHAKE256("meshmark/v1/<method>/perm/" + key)``;
* the whitening bits: ``SHAKE256("meshmark/v1/<method>/white/" + key)``.

Extraction with a wrong key un-permutes and un-whitens with the wrong sequences, so the recovered
bits agree with the expected ones only by chance (probability 1/2 each).
"""
from __future__ import annotations

import hashlib

import numpy as np

from .._core import MeshError


def check_key(key) -> str:
    if isinstance(key, int):
        key = str(key)
    if not isinstance(key, str) or not key:
        raise MeshError("the key must be a non-empty string (or an integer seed)")
    from ..ranges import check_text
    return check_text("key", key)


def _stream(label: str, method: str, key: str, nbytes: int) -> bytes:
    return hashlib.shake_256(f"meshmark/v1/{method}/{label}/".encode() + key.encode("utf-8")).digest(nbytes)


def permutation(key: str, method: str, n: int) -> np.ndarray:
    """A key-dependent permutation of range(n)."""
    words = np.frombuffer(_stream("perm", method, key, 8 * max(n, 1)), dtype="<u8")[:n]
    return np.argsort(words, kind="stable")


def whitening(key: str, method: str, n: int) -> np.ndarray:
    """n key-dependent pseudo-random bits (0/1)."""
    raw = np.frombuffer(_stream("white", method, key, (n + 7) // 8 or 1), np.uint8)
    return np.unpackbits(raw)[:n]


def key_bins(key: str, method: str, K: int, low: float = 0.03, high: float = 0.12) -> int:
    """Key-dependent bin placement (issue 11, docs/security.md §5): the bin count K moved by a
    key-derived fraction in [low, high] of K, up or down (at least one bin, at least 4 bins). Two
    embedders with different keys then use misaligned bins, so a second embedding no longer rewrites
    each of the first one's bins whole."""
    raw = int.from_bytes(_stream("bins", method, key, 8), "little")
    frac = low + (high - low) * ((raw >> 1) / float(1 << 63))
    step = max(1, int(round(K * frac)))
    return max(4, K + step if raw & 1 else K - step)
