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
"""
from __future__ import annotations

import numpy as np

from .. import _core
from ..watermark.cho import _mask


def analyze(V, F=None, K_min: int = 1, K_max: int = 500, eps: float = 0.15, eps2: float = 0.03,
            min_bins: int = 8) -> dict:
    """Run the §6.4 steganalyzer on ``V`` (n, 3) (with faces ``F``: referenced vertices only).

    Returns a dict: ``k_estimate`` (K', 0 if no K could be fitted), ``bhattacharyya`` (D_K'), ``marked``
    (bool), ``eq_6_4_16``, ``eq_6_4_17``, ``min_C``, ``max_Ctilde``, ``size_C``, ``size_Ctilde``, ``balance``,
    ``Ks`` and ``D`` (the curve D_K, -inf where skipped).
    """
    V, mask = _mask(V, F)
    r = _core.cho_steganalysis(V, mask, int(K_min), int(K_max), float(eps), float(eps2), int(min_bins))
    r["Ks"] = np.arange(int(K_min), int(K_max) + 1)
    return r


def gaussian_mixture_2(x, reg_covar: float = 1e-6, tol: float = 1e-3, max_iter: int = 100) -> dict:
    """The native 1-D two-component EM used by :func:`analyze` (``weights``, ``means``, ``variances``,
    ``labels``, ``n_iter``, ``converged``, ``lower_bound``, ``ok``)."""
    return _core.gaussian_mixture_2(np.asarray(x, float).ravel().tolist(), reg_covar, tol, max_iter)


def bhattacharyya_distance(mean1: float, var1: float, mean2: float, var2: float) -> float:
    """Eq. 6.4.14 for two 1-D Gaussians."""
    return _core.bhattacharyya_distance(mean1, var1, mean2, var2)
