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


def _fld(X0, X1, ridge, scatter="pooled"):
    """Fisher linear discriminant w = (S0 + S1 + ridge I)^-1 (m1 - m0) on the rows of X0 / X1.

    ``scatter="pooled"``: S_k the class scatter matrices (sum over the rows: the larger class weighs more);
    ``"balanced"``: S_k / n_k, the class covariances, so that a 10:1 class ratio does not let the stego
    class's covariance decide the direction alone."""
    m0, m1 = X0.mean(0), X1.mean(0)
    n0, n1 = (len(X0), len(X1)) if scatter == "pooled" else (1, 1)
    S = np.cov(X0, rowvar=False, bias=True) * n0 + np.cov(X1, rowvar=False, bias=True) * n1
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
                 search_learners: int = 15, scatter: str = "pooled"):
        if scatter not in ("pooled", "balanced"):
            raise MeshError(f"FLD ensemble: scatter must be 'pooled' or 'balanced', got {scatter!r}")
        self.scatter = scatter
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
            w = _fld(Z[b0][:, S], Z[b1][:, S], self.ridge, self.scatter)
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
        p = {"n_learners": self.n_learners, "d_sub": self.d_sub, "ridge": self.ridge, "seed": self.seed,
             "search_learners": self.search_learners}
        if self.scatter != "pooled":  # only when set: default models' metadata stays exactly as before
            p["scatter"] = self.scatter
        return p

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


def _cv_folds(y, groups, n_folds, seed):
    """Training-side folds for a hyper-parameter or threshold choice: cover-grouped when ``groups`` (the cover
    index of each row) is given, so that a cover and its stego versions never straddle a fold."""
    from sklearn.model_selection import StratifiedGroupKFold, StratifiedKFold
    n_min = int(np.bincount(y).min())
    if groups is not None:
        k = int(max(2, min(n_folds, len(np.unique(groups[y == 0])), len(np.unique(groups[y == 1])))))
        return list(StratifiedGroupKFold(k, shuffle=True, random_state=seed).split(np.zeros(len(y)), y, groups))
    k = int(max(2, min(n_folds, n_min)))
    return list(StratifiedKFold(k, shuffle=True, random_state=seed).split(np.zeros(len(y)), y))


def _to_half(p, t):
    """The monotone piecewise-linear map of [0, 1] onto itself that sends the threshold t to 1/2, so that
    ``predict_proba > 0.5`` is the thresholded decision."""
    p = np.asarray(p, float)
    return np.where(p <= t, 0.5 * p / t, 0.5 + 0.5 * (p - t) / (1 - t))


class Forest:
    """Random forest / extra trees (scikit-learn), class-balanced, for the protocol (not saved in model files).

    ``threshold``: "0.5"; "cv" — the probability cut minimising the training-side P_E = (P_FA + P_MD)/2
    (Kodovský's rule) on out-of-fold probabilities (``folds`` cover-grouped folds when the protocol passes
    the cover groups); "auto" (default) — "cv" when one class has more than 1.5 times the rows of the other
    (the universal detector trained on every stego version: 10:1), else "0.5"."""
    kind = "forest"
    uses_groups = True

    def __init__(self, n_trees: int = 300, trees: str = "random", min_samples_leaf: int = 2,
                 max_features: str | float = "sqrt", threshold: str = "auto", folds: int = 3, seed: int = 0):
        if trees not in ("random", "extra"):
            raise MeshError(f"forest: trees must be 'random' or 'extra', got {trees!r}")
        if threshold not in ("auto", "cv", "0.5"):
            raise MeshError(f"forest: threshold must be 'auto', 'cv' or '0.5', got {threshold!r}")
        self.n_trees, self.trees, self.min_samples_leaf = int(n_trees), trees, int(min_samples_leaf)
        self.max_features, self.threshold, self.folds, self.seed = max_features, threshold, int(folds), int(seed)

    def _model(self):
        from sklearn.ensemble import ExtraTreesClassifier, RandomForestClassifier
        cls = RandomForestClassifier if self.trees == "random" else ExtraTreesClassifier
        return cls(n_estimators=self.n_trees, class_weight="balanced", min_samples_leaf=self.min_samples_leaf,
                   max_features=self.max_features, bootstrap=True, random_state=self.seed, n_jobs=1)

    def fit(self, X, y, groups=None):
        X, y = _check_xy(X, y)
        groups = None if groups is None else np.asarray(groups)
        c = np.bincount(y)
        mode = ("cv" if c.max() > 1.5 * c.min() else "0.5") if self.threshold == "auto" else self.threshold
        self.t = 0.5
        if mode == "cv":
            oof = np.empty(len(y))
            for tr, te in _cv_folds(y, groups, self.folds, self.seed):
                if np.unique(y[tr]).size < 2:  # few covers: a fold trained on one class predicts that class
                    oof[te] = float(y[tr][0])
                    continue
                oof[te] = self._model().fit(X[tr], y[tr]).predict_proba(X[te])[:, 1]
            t, _ = _best_threshold(oof[y == 0], oof[y == 1])
            self.t = float(np.clip(t, 1e-3, 1 - 1e-3))
        self.model = self._model().fit(X, y)
        return self

    def predict_proba(self, X):
        return _to_half(self.model.predict_proba(np.atleast_2d(np.asarray(X, float)))[:, 1], self.t)

    def params(self):
        return {"n_trees": self.n_trees, "trees": self.trees, "min_samples_leaf": self.min_samples_leaf,
                "max_features": self.max_features, "threshold": self.threshold, "folds": self.folds, "seed": self.seed}

    def arrays(self):
        raise MeshError("the forest classifier is for the protocol only: a model file holds plain arrays "
                        "(format 2: ensemble, qda, logreg); train the model with one of those")


class LogReg:
    """L2 logistic regression on standardised features (training mean and deviation), class-balanced
    weights, C chosen from ``Cs`` by the balanced accuracy of ``folds``-fold cross-validation on the
    training side (cover-grouped when the protocol passes the groups) unless ``C`` is given. Decision at
    P = 1/2. ``transform="quantile"`` first maps each feature through its training quantiles to a normal
    (scikit-learn ``QuantileTransformer``; protocol only, not saved in model files)."""
    kind = "logreg"
    uses_groups = True

    def __init__(self, C: float | None = None, Cs=(1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0),
                 folds: int = 3, transform: str = "standard", seed: int = 0):
        if transform not in ("standard", "quantile"):
            raise MeshError(f"logreg: transform must be 'standard' or 'quantile', got {transform!r}")
        self.C, self.Cs, self.folds, self.transform, self.seed = C, tuple(float(c) for c in Cs), int(folds), transform, int(seed)

    def _prep(self, X, fit=False):
        X = np.asarray(X, float)
        if self.transform == "quantile":
            if fit:
                from sklearn.preprocessing import QuantileTransformer
                self.qt = QuantileTransformer(n_quantiles=min(100, len(X)), output_distribution="normal",
                                              random_state=self.seed).fit(X)
            X = self.qt.transform(X)
        if fit:
            self.mean = X.mean(0)
            sd = X.std(0)
            self.scale = np.where(sd > 0, sd, 1.0)
        return (X - self.mean) / self.scale

    @staticmethod
    def _lr(C):
        from sklearn.linear_model import LogisticRegression
        return LogisticRegression(C=C, class_weight="balanced", max_iter=5000)

    def fit(self, X, y, groups=None):
        X, y = _check_xy(X, y)
        C = self.C
        if C is None:
            groups = None if groups is None else np.asarray(groups)
            # folds whose training or test part holds one class only (few covers, grouped by cover) say
            # nothing about C; with none left, C is the middle of Cs
            folds = [(tr, te) for tr, te in _cv_folds(y, groups, self.folds, self.seed)
                     if np.unique(y[tr]).size == 2 and np.unique(y[te]).size == 2]
            score = []
            for c in self.Cs if folds else ():
                acc = []
                for tr, te in folds:
                    Z = self._prep(X[tr], fit=True)
                    pred = self._lr(c).fit(Z, y[tr]).predict(self._prep(X[te]))
                    acc.append(0.5 * ((pred[y[te] == 0] == 0).mean() + (pred[y[te] == 1] == 1).mean()))
                score.append(np.mean(acc))
            C = self.Cs[int(np.argmax(score))] if folds else self.Cs[len(self.Cs) // 2]
        self.C_used = float(C)
        lr = self._lr(C).fit(self._prep(X, fit=True), y)
        self.coef, self.intercept = lr.coef_[0].copy(), float(lr.intercept_[0])
        return self

    def decision(self, X):
        return self._prep(np.atleast_2d(X)) @ self.coef + self.intercept

    def predict_proba(self, X):
        return 1.0 / (1.0 + np.exp(-np.clip(self.decision(X), -700, 700)))

    def params(self):
        return {"C": self.C, "Cs": list(self.Cs), "folds": self.folds, "transform": self.transform, "seed": self.seed}

    def arrays(self):
        if self.transform != "standard":
            raise MeshError("logreg with transform='quantile' is for the protocol only; a model file holds "
                            "plain arrays: use transform='standard'")
        return {"mean": self.mean, "scale": self.scale, "coef": self.coef, "intercept": np.array(self.intercept),
                "C_used": np.array(self.C_used)}

    @classmethod
    def from_arrays(cls, params, a):
        m = cls(**params)
        m.mean, m.scale, m.coef = a["mean"], a["scale"], a["coef"]
        m.intercept, m.C_used = float(a["intercept"]), float(a["C_used"])
        return m


CLASSIFIERS = {"qda": QDA, "ensemble": FLDEnsemble, "forest": Forest, "logreg": LogReg}


def fit(model, X, y, groups=None):
    """``model.fit(X, y)``, passing the cover index of each row to classifiers that choose something by
    cross-validation on the training side (``uses_groups``)."""
    if groups is not None and getattr(model, "uses_groups", False):
        return model.fit(X, y, groups=groups)
    return model.fit(X, y)


def make(kind: str, **params):
    if kind not in CLASSIFIERS:
        raise MeshError(f"unknown classifier {kind!r}; choose from {', '.join(CLASSIFIERS)}")
    return CLASSIFIERS[kind](**params)
