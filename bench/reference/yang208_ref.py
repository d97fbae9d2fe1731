"""Vectorised numpy/scipy reference of YANG208 (thesis §8.1; conventions of docs/steganalysis.md §2: values
floored at 10x their float32 storage-noise bound, regularised log-moments, snapped histograms). For
bench/steganalysis_bench.py (speed ratio) and cross-checks; not used by the package. Meshes whose principal
variances are within 1e-3 of each other (pooled axes) are not covered."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy import stats


U32, C, CAP, S0, SNAP = 2.0 ** -24, 10.0, 0.1, 1e-6, 1e-9


def _moments(x):
    if len(x) == 0:
        return [0.0] * 4
    if len(x) == 1 or np.var(x) == 0:
        return [float(np.mean(x)), 0.0, 0.0, 0.0]
    return [x.mean(), x.var(ddof=1), stats.skew(x), stats.kurtosis(x, fisher=False)]


def _reg_moments(x):
    """mean, var (N - 1), m3 / (m2 + s0)^1.5, m4 / (m2 + s0)^2."""
    if len(x) == 0:
        return [0.0] * 4
    if len(x) == 1:
        return [float(x[0]), 0.0, 0.0, 0.0]
    d = x - x.mean()
    m2, m3, m4 = (d ** 2).mean(), (d ** 3).mean(), (d ** 4).mean()
    return [x.mean(), x.var(ddof=1), m3 / (m2 + S0) ** 1.5, m4 / (m2 + S0) ** 2]


def floored(f, b):
    keep = np.isfinite(f) & (C * b <= CAP)
    return np.maximum(np.abs(f[keep]), C * b[keep])


def _hist(f):
    n = len(f)
    if n < 2 or f.max() == f.min():
        return [0.0] * 4
    q1, q3 = np.percentile(f, [25, 75])
    rng = f.max() - f.min()
    H = np.ceil(rng / (2 * (q3 - q1) / n ** (1 / 3)) - SNAP) if q3 - q1 > SNAP * rng else np.ceil(np.log2(n)) + 1
    if H < 2:
        return [0.0] * 4
    idx = np.minimum(((f - f.min()) * (H / rng) + SNAP).astype(np.int64), int(H) - 1)
    occ, cnt = np.unique(idx, return_counts=True)
    gap = np.diff(occ) > 1
    d = np.where(gap, 0, np.diff(cnt))
    d = np.concatenate([d[~gap], -cnt[:-1][gap], cnt[1:][gap]])
    d = d[d != 0]
    return _moments(np.log(np.abs(d)))


def yang208(V, T, X=None):
    """X: the unit-cube normalised vertices (meshmark._core.unit_cube_normalize) if given."""
    n = len(V)
    used = np.zeros(n, bool)
    used[T] = True
    if X is None:
        c = V[used].mean(0)
        w, U = np.linalg.eigh(np.cov((V[used] - c).T, bias=True))
        X = (V - c) @ U[:, ::-1]
        lo, hi = X[used].min(0), X[used].max(0)
        X = (X - (lo + hi) / 2) / (hi - lo).max() + 0.5
    he = np.vstack([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    key = np.sort(he, axis=1)
    E, inv, fc = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    W = sp.coo_matrix((np.ones(2 * len(E)), (np.r_[E[:, 0], E[:, 1]], np.r_[E[:, 1], E[:, 0]])), (n, n)).tocsr()
    val = np.asarray(W.sum(1)).ravel()
    R = sp.diags(val) - W
    Xs = X - (R @ X) / np.maximum(val, 1)[:, None]
    L, Ls = R @ X, R @ Xs
    interior = np.ones(n, bool)
    interior[E[fc != 2].ravel()] = False
    sel = used & interior & (val > 0)
    out = []
    for cls in (val < 6, val == 6, val > 6):
        m = sel & cls
        d, dl = X[m] - Xs[m], L[m] - Ls[m]
        k = val[m]
        one = np.ones(int(m.sum()))
        for f, b in [*[(x, 2 * U32 * one) for x in np.abs(d).T], (np.linalg.norm(d, axis=1), 2 * np.sqrt(3) * U32 * one),
                     *[(x, 4 * k * U32) for x in np.abs(dl).T],
                     (np.abs(np.linalg.norm(L[m], axis=1) - np.linalg.norm(Ls[m], axis=1)), 4 * np.sqrt(3) * k * U32)]:
            v = floored(f, b)
            out += _reg_moments(np.log(v)) + _hist(v)

    def normals(P):
        nrm = np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]])
        ln = np.linalg.norm(nrm, axis=1)
        return nrm / np.where(ln > 0, ln, 1)[:, None], ln > 0

    def angle(a, b):
        return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))

    N, okN = normals(X)
    Ns, okNs = normals(Xs)

    def noise(P):  # 2 sqrt 3 perimeter / |(b - a) x (c - a)|
        a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
        per = np.linalg.norm(b - a, axis=1) + np.linalg.norm(c - b, axis=1) + np.linalg.norm(a - c, axis=1)
        cr = np.linalg.norm(np.cross(b - a, c - a), axis=1)
        with np.errstate(divide="ignore"):
            return np.where(cr > 0, 2 * np.sqrt(3) * per / np.where(cr > 0, cr, 1), np.inf)

    nu, nus = noise(X), noise(Xs)
    face = np.tile(np.arange(len(T)), 3)
    order = np.argsort(inv.ravel(), kind="stable")
    e_sorted, f_sorted = inv.ravel()[order], face[order]
    start = np.searchsorted(e_sorted, np.arange(len(E)))
    two = fc == 2
    f0, f1 = f_sorted[start[two]], f_sorted[start[two] + 1]
    dih = np.abs(angle(N[f0], N[f1]) - angle(Ns[f0], Ns[f1]))
    bd = U32 * (nu[f0] + nu[f1] + nus[f0] + nus[f1])
    fa, bf = angle(N, Ns), U32 * (nu + nus)
    for f, b in ((dih, bd), (fa, bf)):
        v = floored(f, b)
        out += _reg_moments(np.log(v)) + _hist(v)
    return np.array(out, float)
