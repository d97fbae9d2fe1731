"""The specific steganalyzer against Cho et al.'s mean method (thesis §6.4; docs/radial.md §3).

For every bin number ``K`` in ``[K_min, K_max]`` the vertex norms about the centroid are binned and
normalised as Cho's embedder does, the means ``m_k`` of the non-empty bins (eq. 6.4.13) are fitted by a
two-Gaussian mixture (EM, native), and the separation of the two components is measured by the
Bhattacharyya distance ``D_K`` (eq. 6.4.14). ``K' = argmax D_K`` (eq. 6.4.15) estimates Cho's bin
number; the mesh is declared marked iff the clusters straddle 1/2 symmetrically (eq. 6.4.16,
``eps = 0.15``) and have equal sizes (eq. 6.4.17, ``eps2 = 0.03``).

Not in the thesis: a ``K`` with fewer than ``min_bins = 8`` non-empty bins, or whose fit leaves a
component with fewer than 2 bins, is skipped (a 2-Gaussian fit of 2-4 points is degenerate). The EM
starts from the optimal 2-means split of the sorted means instead of sklearn's seeded k-means++;
otherwise its steps, stopping rule (tol 1e-3) and regularisation (1e-6) are sklearn's.

**The balance rule (docs/steganalysis.md §5).** With ``eps2 = 0.03`` at ``K' = 64``, eq. 6.4.17 accepts
only an exact 32/32 split of the bin means, which a uniformly random 64-bit message gives with
probability C(64, 32) / 2^64 = 9.9 %: the literal rule misses ~90 % of Cho marks carrying random
messages. ``thesis_exact=True`` keeps it. The default replaces eq. 6.4.17 by a two-sided binomial
balance test: under "marked with uniformly random bits" ``|C| ~ Binomial(n, 1/2)`` (``n = |C| + |C~|``,
the non-empty bins at ``K'``), and the split is accepted unless it is in the tails of total
probability at most ``false_reject`` (default 0.01): at most 1 % of random-message marks that pass
eq. 6.4.16 are rejected by the balance rule. At n = 64 this accepts 22..42 ones.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from .. import _core
from .._core import MeshError
from ..watermark.cho import _mask


@lru_cache(maxsize=1024)
def balance_tolerance(n: int, false_reject: float = 0.01) -> int:
    """The largest deviation ``t`` of ``|C|`` from ``n/2`` the balance test accepts: the smallest ``t``
    with ``P(| X - n/2 | > t) <= false_reject`` for ``X ~ Binomial(n, 1/2)`` (``t`` may be a half-integer
    for odd ``n``). MeshError unless ``0 < false_reject < 1``."""
    if not 0 < false_reject < 1:
        raise MeshError(f"false_reject must be in (0, 1), got {false_reject}")
    if n <= 0:
        return 0
    pmf = [math.comb(n, k) / 2.0 ** n for k in range(n + 1)]
    # deviations |k - n/2| in increasing order; tail(t) = P(|X - n/2| > t)
    devs = sorted({abs(k - n / 2) for k in range(n + 1)})
    for t in devs:
        tail = sum(p for k, p in enumerate(pmf) if abs(k - n / 2) > t)
        if tail <= false_reject:
            return t
    return devs[-1]


def balance_p_value(size_C: int, size_Ctilde: int) -> float:
    """Two-sided binomial p-value of the split ``size_C / size_Ctilde`` under p = 1/2."""
    n = int(size_C) + int(size_Ctilde)
    if n == 0:
        return 1.0
    d = abs(size_C - n / 2)
    return float(min(1.0, sum(math.comb(n, k) for k in range(n + 1) if abs(k - n / 2) >= d) / 2.0 ** n))


def analyze(V, F=None, K_min: int = 1, K_max: int = 500, eps: float = 0.15, eps2: float = 0.03,
            min_bins: int = 8, thesis_exact: bool = False, false_reject: float = 0.01) -> dict:
    """Run the §6.4 steganalyzer on ``V`` (n, 3) (with faces ``F``: referenced vertices only).

    ``thesis_exact=True``: eq. 6.4.17 as printed (``| |C| - |C~| | / K' <= eps2``). Default: the binomial
    balance test with false-reject rate ``false_reject`` (module docstring); ``eps2`` is then unused.

    Returns a dict: ``k_estimate`` (K', 0 if no K could be fitted), ``bhattacharyya`` (D_K'), ``marked``
    (bool), ``eq_6_4_16``, ``eq_6_4_17`` (the literal rule), ``balance_test`` (the rule used), ``p_balance``
    (binomial p-value of the split), ``min_C``, ``max_Ctilde``, ``size_C``, ``size_Ctilde``, ``balance``,
    ``Ks`` and ``D`` (the curve D_K, -inf where skipped).
    """
    V, mask = _mask(V, F)
    if not thesis_exact:
        balance_tolerance(1, false_reject)  # validates false_reject before any work
    r = _core.cho_steganalysis(V, mask, int(K_min), int(K_max), float(eps), float(eps2), int(min_bins))
    r["Ks"] = np.arange(int(K_min), int(K_max) + 1)
    c, ct = int(r["size_C"]), int(r["size_Ctilde"])
    r["p_balance"] = balance_p_value(c, ct)
    if thesis_exact:
        r["balance_test"] = bool(r["eq_6_4_17"])
    else:
        r["balance_test"] = bool(c + ct > 0 and abs(c - (c + ct) / 2) <= balance_tolerance(c + ct, false_reject))
    r["marked"] = bool(r["eq_6_4_16"] and r["balance_test"] and r["k_estimate"] > 0)
    r["thesis_exact"] = bool(thesis_exact)
    return r


def gaussian_mixture_2(x, reg_covar: float = 1e-6, tol: float = 1e-3, max_iter: int = 100) -> dict:
    """The native 1-D two-component EM used by :func:`analyze` (``weights``, ``means``, ``variances``,
    ``labels``, ``n_iter``, ``converged``, ``lower_bound``, ``ok``)."""
    return _core.gaussian_mixture_2(np.asarray(x, float).ravel().tolist(), reg_covar, tol, max_iter)


def bhattacharyya_distance(mean1: float, var1: float, mean2: float, var2: float) -> float:
    """Eq. 6.4.14 for two 1-D Gaussians."""
    return _core.bhattacharyya_distance(mean1, var1, mean2, var2)
