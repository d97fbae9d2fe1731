"""Classifiers for feature-based steganalysis (thesis §8.1.5 and Kodovský et al. 2012).

* :class:`MinMaxScaler` — eq. 8.1.5, fitted on the training features only (a constant training
  feature maps to 0).
* :class:`QDA` — the thesis' quadratic discriminant: scaling, optional PCA to ``n_components``
  (Figs. 8.3-8.5, scikit-learn's PCA), Gaussian classes with covariance ``(1 - reg_param) S + reg_param I``
  (scikit-learn's ``reg_param`` rule, computed here; the covariance is shrunk towards the identity: with 208 features and a few hundred training meshes the class
  covariances are singular, and MATLAB's ``classify`` the thesis used would refuse them).
* :class:`FLDEnsemble` — the ensemble classifier of Kodovský, Fridrich and Holub (IEEE TIFS 2012),
  the standard of the field: ``n_learners`` Fisher linear discriminants, each on a random subspace of
  ``d_sub`` features and a bootstrap sample of the training set, each thresholded to minimise its
  own training P_E, combined by majority vote. ``d_sub`` is chosen by the out-of-bag error over a
  grid of 5 % .. 100 % of the features (15 learners per candidate; the authors' code searches it too)
  unless given.

Every classifier is fitted with scikit-learn / numpy and then keeps only plain arrays, so that a model
file is an ``.npz`` read with ``allow_pickle=False`` (no code runs when a model is loaded).
``predict_proba(X)`` returns P(stego) per row; for the ensemble it is the fraction of votes.
"""
from __future__ import annotations

import numpy as np

from .._core import MeshError


def _check_xy(X, y):
    X = np.asarray(X, dtype=np.float64)
    y = np.asarray(y).astype(int).ravel()
    if X.ndim != 2 or X.shape[0] == 0:
        raise MeshError("empty training set: no feature vectors")
    if len(y) != len(X):
        raise MeshError(f"{len(X)} feature vectors but {len(y)} labels")
    if not np.isin(y, (0, 1)).all():
        raise MeshError("labels must be 0 (cover) and 1 (stego)")
    counts = np.bincount(y, minlength=2)
    if counts.min() == 0:
        raise MeshError(f"training needs both covers and stego meshes; got {counts[0]} covers and {counts[1]} stego")
    if not np.isfinite(X).all():
        raise MeshError("training features contain NaN or Inf")
    return X, y


class MinMaxScaler:
    """eq. 8.1.5: f' = (f - f_min) / (f_max - f_min) with f_min, f_max from the training set."""

    def fit(self, X):
        X = np.asarray(X, float)
        self.lo = X.min(0)
        span = X.max(0) - self.lo
        self.span = np.where(span > 0, span, 1.0)
        return self

    def transform(self, X):
        return (np.asarray(X, float) - self.lo) / self.span

    def arrays(self, p=""):
        return {p + "lo": self.lo, p + "span": self.span}

    @classmethod
    def from_arrays(cls, a, p=""):
        s = cls()
        s.lo, s.span = a[p + "lo"], a[p + "span"]
        return s


class QDA:
    kind = "qda"

    def __init__(self, n_components: int | None = None, reg_param: float = 0.1):
        self.n_components = n_components
        self.reg_param = float(reg_param)

    def fit(self, X, y):
        from sklearn.decomposition import PCA

        X, y = _check_xy(X, y)
        self.scaler = MinMaxScaler().fit(X)
        Z = self.scaler.transform(X)
        self.pca_mean = np.zeros(Z.shape[1])
        self.pca_components = np.eye(Z.shape[1])
        if self.n_components:
            k = int(min(self.n_components, Z.shape[1], Z.shape[0] - 1))
            p = PCA(n_components=k, svd_solver="full").fit(Z)
            self.pca_mean, self.pca_components = p.mean_, p.components_
        Z = (Z - self.pca_mean) @ self.pca_components.T
        # Per-class Gaussian with covariance (1 - r) S_k + r I, S_k the sample covariance (/n): the
        # reg_param rule of sklearn's QuadraticDiscriminantAnalysis (whose fitted attributes and solvers
        # changed between releases; these 10 lines keep the model file independent of them).
        means, rots, scal, pri = [], [], [], []
        for k in (0, 1):
            Zk = Z[y == k]
            mu = Zk.mean(0)
            C = np.atleast_2d(np.cov(Zk, rowvar=False, bias=True)) if len(Zk) > 1 else np.zeros((Z.shape[1],) * 2)
            C = (1 - self.reg_param) * C + self.reg_param * np.eye(C.shape[0])
            w, U = np.linalg.eigh(C)
            means.append(mu), rots.append(U), scal.append(np.maximum(w, 1e-12)), pri.append(len(Zk) / len(Z))
        self.means, self.rotations, self.scalings = np.array(means), np.array(rots), np.array(scal)
        self.log_priors = np.log(np.array(pri))
        return self

    def decision(self, X):
        """log P(stego | x) - log P(cover | x) (sklearn's QDA decision rule, from the stored arrays)."""
        Z = (self.scaler.transform(np.atleast_2d(X)) - self.pca_mean) @ self.pca_components.T
        ll = []
        for k in range(2):
            S = self.scalings[k]
            Xm = (Z - self.means[k]) @ self.rotations[k]
            ll.append(-0.5 * (np.sum(Xm ** 2 / S, axis=1) + np.sum(np.log(S))) + self.log_priors[k])
        return ll[1] - ll[0]

    def predict_proba(self, X):
        return 1.0 / (1.0 + np.exp(-np.clip(self.decision(X), -700, 700)))

    def params(self):
        return {"n_components": self.n_components, "reg_param": self.reg_param}

    def arrays(self):
        return {**self.scaler.arrays("scaler_"), "pca_mean": self.pca_mean, "pca_components": self.pca_components,
                "means": self.means, "rotations": self.rotations, "scalings": self.scalings,
                "log_priors": self.log_priors}

    @classmethod
    def from_arrays(cls, params, a):
        q = cls(**params)
        q.scaler = MinMaxScaler.from_arrays(a, "scaler_")
        for k in ("pca_mean", "pca_components", "means", "rotations", "scalings", "log_priors"):
            setattr(q, k, a[k])
        return q


def _fld(X0, X1, ridge):
    """Fisher linear discriminant w = (S0 + S1 + ridge I)^-1 (m1 - m0) on the rows of X0 / X1."""
    m0, m1 = X0.mean(0), X1.mean(0)
    S = np.cov(X0, rowvar=False, bias=True) * len(X0) + np.cov(X1, rowvar=False, bias=True) * len(X1)
    S = np.atleast_2d(S)
    lam = ridge * max(np.trace(S) / S.shape[0], 1e-300)
    w = np.linalg.solve(S + lam * np.eye(S.shape[0]), m1 - m0)
    return w


def _best_threshold(p0, p1):
    """Threshold on projections minimising P_E = (P_FA + P_MD) / 2 (Kodovský's rule); stego above."""
    v = np.concatenate([p0, p1])
    lab = np.concatenate([np.zeros(len(p0)), np.ones(len(p1))])
    o = np.argsort(v, kind="stable")
    v, lab = v[o], lab[o]
    # threshold between v[i-1] and v[i]: covers below are correct, stego above are correct
    c0 = np.concatenate([[0], np.cumsum(lab == 0)])  # covers at or below each cut
    c1 = np.concatenate([[0], np.cumsum(lab == 1)])
    pfa = 1 - c0 / len(p0)
    pmd = c1 / len(p1)
    pe = (pfa + pmd) / 2
    i = int(np.argmin(pe))
    if i == 0:
        return v[0] - 1.0, pe[i]
    if i == len(v):
        return v[-1] + 1.0, pe[i]
    return 0.5 * (v[i - 1] + v[i]), pe[i]


class FLDEnsemble:
    kind = "ensemble"

    def __init__(self, n_learners: int = 51, d_sub: int | None = None, ridge: float = 1e-6, seed: int = 0,
                 search_learners: int = 15):
        self.n_learners = int(n_learners)
        self.search_learners = int(search_learners)
        self.d_sub = d_sub
        self.ridge = float(ridge)
        self.seed = int(seed)

    def _train(self, Z, y, d_sub, rng):
        n, d = Z.shape
        subsets = np.empty((self.n_learners, d_sub), np.int64)
        W = np.empty((self.n_learners, d_sub))
        b = np.empty(self.n_learners)
        oob_votes = np.zeros(n)
        oob_count = np.zeros(n)
        i0, i1 = np.flatnonzero(y == 0), np.flatnonzero(y == 1)
        for l in range(self.n_learners):
            S = np.sort(rng.choice(d, d_sub, replace=False))
            b0 = rng.choice(i0, len(i0), replace=True)  # bootstrap within each class
            b1 = rng.choice(i1, len(i1), replace=True)
            w = _fld(Z[b0][:, S], Z[b1][:, S], self.ridge)
            t, _ = _best_threshold(Z[b0][:, S] @ w, Z[b1][:, S] @ w)
            subsets[l], W[l], b[l] = S, w, t
            oob = np.ones(n, bool)
            oob[b0] = False
            oob[b1] = False
            oob_votes[oob] += (Z[oob][:, S] @ w > t)
            oob_count[oob] += 1
        seen = oob_count > 0
        pred = oob_votes[seen] / oob_count[seen] > 0.5
        yy = y[seen]
        oob_pe = 0.5 * ((pred[yy == 0]).mean() if (yy == 0).any() else 0) + \
            0.5 * ((~pred[yy == 1]).mean() if (yy == 1).any() else 0)
        return subsets, W, b, float(oob_pe)

    def fit(self, X, y):
        X, y = _check_xy(X, y)
        self.scaler = MinMaxScaler().fit(X)
        Z = self.scaler.transform(X)
        d = Z.shape[1]
        n_min = int(np.bincount(y).min())
        cap = max(1, min(d, 2 * n_min - 2))
        if self.d_sub:
            ds = int(min(self.d_sub, d))
        else:  # the out-of-bag search of d_sub (Kodovský et al. §IV-B), on search_learners learners per candidate
            grid = sorted({max(1, min(cap, int(round(d * f)))) for f in (0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0)})
            L, self.n_learners = self.n_learners, min(self.n_learners, self.search_learners)
            try:
                errs = [self._train(Z, y, g, np.random.default_rng(self.seed))[3] for g in grid]
            finally:
                self.n_learners = L
            ds = grid[int(np.argmin(errs))]
        best = self._train(Z, y, ds, np.random.default_rng(self.seed)) + (ds,)
        self.subsets, self.W, self.b, self.oob_error, self.d_sub_used = best
        return self

    def votes(self, X):
        Z = self.scaler.transform(np.atleast_2d(X))
        proj = np.einsum("nld,ld->nl", Z[:, self.subsets], self.W)
        return proj > self.b

    def predict_proba(self, X):
        return self.votes(X).mean(axis=1)

    def params(self):
        return {"n_learners": self.n_learners, "d_sub": self.d_sub, "ridge": self.ridge, "seed": self.seed,
                "search_learners": self.search_learners}

    def arrays(self):
        return {**self.scaler.arrays("scaler_"), "subsets": self.subsets, "W": self.W, "b": self.b,
                "oob_error": np.array(self.oob_error), "d_sub_used": np.array(self.d_sub_used)}

    @classmethod
    def from_arrays(cls, params, a):
        e = cls(**params)
        e.scaler = MinMaxScaler.from_arrays(a, "scaler_")
        e.subsets, e.W, e.b = a["subsets"], a["W"], a["b"]
        e.oob_error, e.d_sub_used = float(a["oob_error"]), int(a["d_sub_used"])
        return e


CLASSIFIERS = {"qda": QDA, "ensemble": FLDEnsemble}


def make(kind: str, **params):
    if kind not in CLASSIFIERS:
        raise MeshError(f"unknown classifier {kind!r}; choose from {', '.join(CLASSIFIERS)}")
    return CLASSIFIERS[kind](**params)
