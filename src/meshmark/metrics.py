"""Distortion and watermark metrics.

Watermark measures compare an embedded bit sequence ``w`` with an extracted one ``w2`` (arrays of
0/1 or -1/+1, same length):

* :func:`correlation` — the correlation coefficient C(w, w') of eq. 6.3.11;
* :func:`normalized_correlation` — NC = sum(w w') / sqrt(sum(w^2) sum(w'^2)) on the +-1 form
  (equal to C when both sequences have zero mean);
* :func:`cdr` — correct detection rate, the fraction of bits that agree; :func:`bit_error_rate` = 1 - CDR;
* :func:`false_alarm_probability` — P(X >= matches), X ~ Binomial(n, 1/2): the chance that a random
  sequence agrees with ``w`` on at least as many bits. The detection decision uses it.
"""
from __future__ import annotations

import math

import numpy as np

from ._core import MeshError


def _pm1(w, name: str) -> np.ndarray:
    a = np.asarray(w)
    if a.ndim != 1:
        raise MeshError(f"{name} must be a 1-D bit sequence, got shape {a.shape}")
    if a.size and not np.isin(a, (-1, 0, 1)).all():
        raise MeshError(f"{name} must hold bits (0/1 or -1/+1)")
    return np.where(a > 0, 1.0, -1.0)


def _pair(w, w2):
    a, b = _pm1(w, "w"), _pm1(w2, "w2")
    if a.shape != b.shape:
        raise MeshError(f"bit sequences differ in length: {a.size} and {b.size}")
    if a.size == 0:
        raise MeshError("empty bit sequences")
    return a, b


def correlation(w, w2) -> float:
    """C(w, w') of eq. 6.3.11 (Pearson correlation of the +-1 sequences); 0 if either is constant."""
    a, b = _pair(w, w2)
    a, b = a - a.mean(), b - b.mean()
    den = math.sqrt(float((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / den) if den > 0 else 0.0


def normalized_correlation(w, w2) -> float:
    """NC = mean(w_i w'_i) on the +-1 form (= 2 CDR - 1)."""
    a, b = _pair(w, w2)
    return float((a * b).mean())


def cdr(w, w2) -> float:
    """Correct detection rate: the fraction of equal bits."""
    a, b = _pair(w, w2)
    return float((a == b).mean())


def bit_error_rate(w, w2) -> float:
    """1 - CDR."""
    return 1.0 - cdr(w, w2)


def false_alarm_probability(matches: int, n: int) -> float:
    """P(X >= matches) for X ~ Binomial(n, 1/2), computed exactly with integers."""
    if n < 0 or not 0 <= matches <= max(n, 0):
        raise MeshError(f"need 0 <= matches <= n, got matches={matches}, n={n}")
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, k) for k in range(matches, n + 1))
    return float(tail / (1 << n)) if n < 1000 else math.exp(math.log(tail) - n * math.log(2))
