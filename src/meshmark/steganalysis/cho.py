"""The specific steganalyzer against Cho et al.'s mean method (thesis §6.4; docs/radial.md §3).

For every bin number ``K`` in ``[K_min, K_max]`` (at most the number of vertices: a Cho mark has one
bin per bit and at most one bit per vertex) the vertex norms about the centroid are binned and
normalised as Cho's embedder does and the bin means ``m_k`` are taken (eq. 6.4.13). Two decision rules
read them (native, ``cho_steganalysis.h``):

**The margin rule (default, ``rule="margin"``; not in the thesis, docs/radial.md §3.2).** Cho's mean
method moves the mean of every bin to at least 1/2 + alpha or at most 1/2 - alpha, so read with the
embedding K no bin mean lies near 1/2; read with any other K, or on a clean mesh, the bin means spread
continuously through 1/2. For each K, with ``h`` the ``(trim + 1)``-th smallest ``|m_k - 1/2|`` over the
bins holding at least ``min_count`` vertices (n of them), the p-value of "at most ``trim`` bins closer to
1/2 than h" is ``p_K = P(Binomial(n, q) <= trim)``, ``q`` the null probability of ``|m - 1/2| < h`` under
the more conservative of two normal fits (centred, from the median ``|m - 1/2|``; and from the mean and
standard deviation of ``m - 1/2``). ``K'' = argmin p_K``; the mesh is declared marked iff
``n_tests * min p_K <= false_alarm`` (Bonferroni over the K scanned), so the rate at which clean meshes
are called marked is at most ``false_alarm`` whenever the per-K null holds.

**The thesis' rule (``rule="thesis"``).** The means of the non-empty bins are fitted by a two-Gaussian
mixture (EM, native), the separation is the Bhattacharyya distance ``D_K`` (eq. 6.4.14), ``K' = argmax
D_K`` (eq. 6.4.15), and the mesh is marked iff the clusters straddle 1/2 symmetrically (eq. 6.4.16,
``eps = 0.15``) and have equal sizes (eq. 6.4.17, ``eps2 = 0.03``; ``thesis_exact=True``) or pass the
two-sided binomial balance test of docs/steganalysis.md §5 (``false_reject``; the default of this rule).
Not in the thesis: a ``K`` with fewer than ``min_bins`` non-empty bins, or whose fit leaves a component
with fewer than 2 bins, is skipped; the EM starts from the optimal 2-means split of the sorted means.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from .. import _core
from .._core import MeshError
from ..ranges import MAX_COUNT, ParameterError, check_bool, check_float, check_int
from ..mesh import FacesLike, MeshLike, vertices_and_mask
from .._typing import ArrayLike

RULES = ("margin", "thesis")
#: largest K_max: a scan to K visits about K^2 / 2 bins (the EM fits of the thesis' rule ~100 times that);
#: 100,000 is 200 times the thesis' 500 and bounds a margin scan to about a minute
MAX_K_SCAN = 100_000


@lru_cache(maxsize=1024)
def balance_tolerance(n: int, false_reject: float = 0.01) -> int:
    """The largest deviation ``t`` of ``|C|`` from ``n/2`` the balance test accepts: the smallest ``t``
    with ``P(| X - n/2 | > t) <= false_reject`` for ``X ~ Binomial(n, 1/2)`` (``t`` may be a half-integer
    for odd ``n``). MeshError unless ``0 < false_reject < 1``."""
    false_reject = check_float("false_reject", false_reject, 0.0, 1.0, low_open=True, high_open=True)
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


def check_options(K_min: int = 1, K_max: int = 500, rule: str | None = None, false_alarm: float = 0.01,
                  trim: int = 3, min_count: int = 5, eps: float = 0.15, eps2: float = 0.03,
                  min_bins: int = 8, thesis_exact: bool = False, false_reject: float = 0.01) -> dict:
    """Every option of :func:`analyze` against its documented range (docs/radial.md §3.3), before any
    work: a :class:`~meshmark.ranges.ParameterError` naming the option otherwise. Returns them resolved
    (``rule`` None -> "thesis" with ``thesis_exact``, else "margin"). ``eps`` and ``eps2`` are unitless
    tolerances on the normalised bin means (in [0, 1]) and on cluster sizes; ``false_alarm`` and
    ``false_reject`` are probabilities."""
    o = {"K_min": check_int("K_min", K_min, 1, MAX_K_SCAN), "K_max": check_int("K_max", K_max, 1, MAX_K_SCAN)}
    if o["K_max"] < o["K_min"]:
        raise ParameterError("K_max", f"K_max must be at least K_min = {o['K_min']}, got {o['K_max']}")
    o["thesis_exact"] = check_bool("thesis_exact", thesis_exact)
    if rule is None:
        rule = "thesis" if o["thesis_exact"] else "margin"
    if rule not in RULES:
        raise ParameterError("rule", f"rule must be one of {', '.join(RULES)}, got {rule!r}")
    if o["thesis_exact"] and rule != "thesis":
        raise ParameterError("thesis_exact", "thesis_exact is the literal eq. 6.4.17 of the thesis' rule; "
                                             f"it does not apply to rule={rule!r}")
    o["rule"] = rule
    o["false_alarm"] = check_float("false_alarm", false_alarm, 0.0, 1.0, low_open=True, high_open=True)
    o["trim"] = check_int("trim", trim, 0, 100)
    o["min_count"] = check_int("min_count", min_count, 1, MAX_COUNT)
    o["eps"] = check_float("eps", eps, 0.0, 0.5)
    o["eps2"] = check_float("eps2", eps2, 0.0, 1.0)
    o["min_bins"] = check_int("min_bins", min_bins, 2, MAX_K_SCAN)
    o["false_reject"] = check_float("false_reject", false_reject, 0.0, 1.0, low_open=True, high_open=True)
    return o


def analyze(V: MeshLike, F: FacesLike = None, K_min: int = 1, K_max: int = 500, rule: str | None = None,
            false_alarm: float = 0.01,
            trim: int = 3, min_count: int = 5, eps: float = 0.15, eps2: float = 0.03, min_bins: int = 8,
            thesis_exact: bool = False, false_reject: float = 0.01, fit_em: bool = True) -> dict:
    """Run the §6.4 steganalyzer on ``V`` (n, 3) (with faces ``F``: referenced vertices only).

    ``rule``: "margin" (default) or "thesis" (``thesis_exact=True`` selects it with the literal eq.
    6.4.17). Both rules are evaluated (the EM fits only with ``fit_em``, required by ``rule="thesis"``);
    ``k_estimate`` and ``marked`` are those of the chosen rule.

    Returns a dict:

    * ``rule``, ``k_estimate``, ``marked``, ``Ks`` (the K scanned, ``K_min .. K_max_used``), ``K_max_used``;
    * the margin rule: ``k_margin`` (K''), ``marked_margin``, ``p_value`` (the scan's corrected p,
      ``min(1, n_tests * min p_K)``), ``p_min`` (min p_K), ``n_tests``, ``log10_p`` (curve, NaN where no
      test), ``hole`` (curve h), ``n_bins`` (curve, bins with >= ``min_count`` vertices), ``margin`` (h at
      K''), ``q`` (its null probability), ``margin_bins``, ``margin_above`` (bins above 1/2: the 1 bits);
    * the thesis' rule: ``k_thesis`` (K'), ``marked_thesis``, ``bhattacharyya`` (D_K'), ``D`` (curve,
      -inf where skipped), ``loglik`` (the EM fit's mean log-likelihood per K), ``eq_6_4_16``,
      ``eq_6_4_17`` (literal), ``balance_test`` (the balance rule used), ``p_balance``, ``min_C``,
      ``max_Ctilde``, ``size_C``, ``size_Ctilde``, ``balance``, ``thesis_exact``.
    """
    o = check_options(K_min, K_max, rule, false_alarm, trim, min_count, eps, eps2, min_bins, thesis_exact,
                      false_reject)
    fit_em = check_bool("fit_em", fit_em)
    if o["rule"] == "thesis" and not fit_em:
        raise ParameterError("fit_em", "the thesis' rule needs the EM fits (fit_em=True)")
    V, mask = vertices_and_mask(V, F)
    r = _core.cho_steganalysis(V, mask, o["K_min"], o["K_max"], o["eps"], o["eps2"], o["min_bins"], 1e-6, fit_em,
                               o["trim"], o["min_count"], o["false_alarm"])
    r["Ks"] = np.arange(o["K_min"], int(r["K_max_used"]) + 1)
    # the thesis' rule: eqs. 6.4.14-6.4.17 with the chosen balance rule
    c, ct = int(r["size_C"]), int(r["size_Ctilde"])
    r["p_balance"] = balance_p_value(c, ct)
    if o["thesis_exact"]:
        r["balance_test"] = bool(r["eq_6_4_17"])
    else:
        r["balance_test"] = bool(c + ct > 0 and abs(c - (c + ct) / 2) <= balance_tolerance(c + ct, o["false_reject"]))
    r["k_thesis"] = int(r.pop("k_estimate"))
    del r["marked"]  # the native decision is the literal eqs. 6.4.16-17; the balance rule is chosen here
    r["marked_thesis"] = bool(r["eq_6_4_16"] and r["balance_test"] and r["k_thesis"] > 0)
    r["thesis_exact"] = o["thesis_exact"]
    # the margin rule
    r["marked_margin"] = bool(r.pop("margin_marked"))
    r["log10_p"] = np.asarray(r.pop("log_p")) / math.log(10)
    r["p_value"] = float(math.exp(r.pop("log_p_scan"))) if r["n_tests"] else 1.0
    r["p_min"] = float(math.exp(r.pop("log_p_min"))) if r["n_tests"] else 1.0
    r["rule"] = o["rule"]
    r["k_estimate"] = r["k_margin"] if o["rule"] == "margin" else r["k_thesis"]
    r["marked"] = r["marked_margin"] if o["rule"] == "margin" else r["marked_thesis"]
    return r


def margin_test(means: ArrayLike, counts: ArrayLike, trim: int = 3, min_count: int = 5, min_bins: int = 8) -> dict:
    """The native margin test of one K (docs/radial.md §3.2) on bin means (K,) and counts (K,):
    ``ok``, ``log_p`` (natural log of p), ``hole`` (h), ``q``, ``n_bins``, ``n_above``."""
    return _core.cho_margin_test(np.asarray(means, float).ravel().tolist(), np.asarray(counts, int).ravel().tolist(),
                                 check_int("trim", trim, 0, 100), check_int("min_count", min_count, 1, MAX_COUNT),
                                 check_int("min_bins", min_bins, 2, MAX_K_SCAN))


def gaussian_mixture_2(x: ArrayLike, reg_covar: float = 1e-6, tol: float = 1e-3, max_iter: int = 100) -> dict:
    """The native 1-D two-component EM used by :func:`analyze` (``weights``, ``means``, ``variances``,
    ``labels``, ``n_iter``, ``converged``, ``lower_bound``, ``ok``).

    ``x``: (k,) samples."""
    return _core.gaussian_mixture_2(np.asarray(x, float).ravel().tolist(), reg_covar, tol, max_iter)


def bhattacharyya_distance(mean1: float, var1: float, mean2: float, var2: float) -> float:
    """Eq. 6.4.14 for two 1-D Gaussians."""
    return _core.bhattacharyya_distance(mean1, var1, mean2, var2)


__all__ = ["RULES", "MAX_K_SCAN", "analyze", "check_options", "margin_test", "balance_tolerance", "balance_p_value", "gaussian_mixture_2",
           "bhattacharyya_distance", "MeshError"]
