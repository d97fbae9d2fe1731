"""The classifier options added for detector accuracy (docs/steganalysis.md §6, "Stronger classifiers"):
the FLD ensemble's class-weighted scatter, cross-validated logistic regression, random forests with a
training-side P_E threshold, and the cover-grouped folds they use."""
import json

import numpy as np
import pytest
from scipy.stats import norm
from sklearn.discriminant_analysis import LinearDiscriminantAnalysis
from sklearn.linear_model import LogisticRegression

from meshmark import MeshError
from meshmark.steganalysis import classifiers as clf
from meshmark.steganalysis import protocol as P
from meshmark.steganalysis.model import Model


def two_gaussians(n0, n1, d=8, dist=2.0, seed=0):
    """N(0, I) covers against N(mu, I) stego with |mu| = dist: Bayes P_E = Phi(-dist / 2) (0.1587 at 2)."""
    rng = np.random.default_rng(seed)
    mu = rng.normal(size=d)
    mu *= dist / np.linalg.norm(mu)
    X = np.vstack([rng.normal(size=(n0, d)), rng.normal(size=(n1, d)) + mu])
    return X * rng.uniform(0.1, 10, d), np.r_[np.zeros(n0), np.ones(n1)].astype(int)  # unequal feature scales


def pe(y, p):
    pred = np.asarray(p) > 0.5
    return 0.5 * (pred[y == 0].mean() + (~pred[y == 1]).mean())


BAYES = norm.cdf(-1.0)


def test_balanced_scatter_is_equal_prior_lda_and_default_unchanged():
    rng = np.random.default_rng(1)
    X0 = rng.normal(size=(60, 4)) * [1, 2, 3, 4]
    X1 = rng.normal(size=(600, 4)) @ rng.normal(size=(4, 4)) + 1.0  # 10:1, different covariances
    X, y = np.vstack([X0, X1]), np.r_[np.zeros(60), np.ones(600)].astype(int)

    def cos(a, b):
        return a @ b / np.linalg.norm(a) / np.linalg.norm(b)
    lda_eq = LinearDiscriminantAnalysis(solver="eigen", priors=[0.5, 0.5]).fit(X, y).coef_[0]
    lda_emp = LinearDiscriminantAnalysis(solver="eigen").fit(X, y).coef_[0]
    assert cos(clf._fld(X0, X1, 1e-12, "balanced"), lda_eq) == pytest.approx(1, abs=1e-9)
    assert cos(clf._fld(X0, X1, 1e-12), lda_emp) == pytest.approx(1, abs=1e-9)
    assert cos(lda_eq, lda_emp) < 0.99  # the two really differ here
    # the default ensemble: same votes as before the option existed, and no new key in a model's metadata
    a = clf.FLDEnsemble(n_learners=7, seed=2).fit(X, y)
    b = clf.FLDEnsemble(n_learners=7, seed=2, scatter="pooled").fit(X, y)
    assert np.array_equal(a.W, b.W) and "scatter" not in a.params()
    c = clf.FLDEnsemble(n_learners=7, seed=2, scatter="balanced").fit(X, y)
    assert c.params()["scatter"] == "balanced" and not np.allclose(a.W, c.W)
    with pytest.raises(MeshError, match="scatter must be"):
        clf.FLDEnsemble(scatter="weighted")


def test_logreg_reaches_the_bayes_error_and_agrees_with_sklearn():
    X_all, y_all = two_gaussians(6000, 6000, seed=3)
    tr = np.random.default_rng(0).permutation(len(y_all)) < 3000
    X, y, Xt, yt = X_all[tr], y_all[tr], X_all[~tr], y_all[~tr]
    m = clf.LogReg().fit(X, y)
    assert m.C_used in m.Cs
    assert abs(pe(yt, m.predict_proba(Xt)) - BAYES) < 0.02  # the Bayes classifier is linear here
    Z = (X - X.mean(0)) / X.std(0)
    sk = LogisticRegression(C=m.C_used, class_weight="balanced", max_iter=5000).fit(Z, y)
    np.testing.assert_allclose(m.predict_proba(Xt), sk.predict_proba((Xt - X.mean(0)) / X.std(0))[:, 1], atol=1e-4)
    # 10:1 stego:cover: balanced weights keep the balanced error near Bayes instead of calling everything stego
    idx = np.r_[np.flatnonzero(y == 0)[:150], np.flatnonzero(y == 1)[:1500]]
    m = clf.LogReg(C=1.0).fit(X[idx], y[idx])
    assert abs(pe(yt, m.predict_proba(Xt)) - BAYES) < 0.03
    q = clf.LogReg(transform="quantile").fit(X, y)
    assert abs(pe(yt, q.predict_proba(Xt)) - BAYES) < 0.03


def test_forest_threshold_on_imbalanced_training():
    X_all, y_all = two_gaussians(3000, 3000, d=4, seed=5)
    tr = np.random.default_rng(1).permutation(len(y_all)) < 3300
    X, y, Xt, yt = X_all[tr], y_all[tr], X_all[~tr], y_all[~tr]
    idx = np.r_[np.flatnonzero(y == 0)[:150], np.flatnonzero(y == 1)[:1500]]  # 10:1 like the universal "all"
    f = clf.Forest(n_trees=100).fit(X[idx], y[idx])
    assert 0 < f.t < 1 and f.t != 0.5  # "auto": cross-validated P_E threshold on imbalanced data
    p = f.predict_proba(Xt)
    assert 0 <= p.min() and p.max() <= 1
    assert BAYES - 0.02 < pe(yt, p) < BAYES + 0.08
    # the threshold map is monotone and sends t to 1/2
    np.testing.assert_allclose(clf._to_half([0, f.t, 1], f.t), [0, 0.5, 1])
    g = clf.Forest(n_trees=100, threshold="0.5").fit(X[idx], y[idx])
    assert g.t == 0.5
    with pytest.raises(MeshError, match="protocol only"):
        f.arrays()
    with pytest.raises(MeshError, match="trees must be"):
        clf.Forest(trees="boosted")


def test_grouped_folds_keep_a_cover_with_its_stego():
    groups = np.repeat(np.arange(40), 5)  # 40 covers, each with 4 stego versions
    y = np.tile([0, 1, 1, 1, 1], 40)
    for tr, te in clf._cv_folds(y, groups, 3, 0):
        assert not set(groups[tr]) & set(groups[te]) and (y[te] == 0).any() and (y[te] == 1).any()


def test_logreg_model_file_roundtrip(tmp_path):
    X, y = two_gaussians(60, 60, d=208, seed=4)
    lab = np.where(y == 1, "a", "cover")
    m = Model.train(X, y, lab, "yang208", "logreg", {"corpus_hash": "x"})
    m.save(tmp_path / "m.npz")
    m2 = Model.load(tmp_path / "m.npz")
    assert m.detect_features(X[3]) == m2.detect_features(X[3])
    meta = json.loads(bytes(np.load(tmp_path / "m.npz")["meta"]).decode())
    assert meta["format_version"] == 3 and meta["detectors"]["universal"]["kind"] == "logreg"
    with pytest.raises(MeshError, match="protocol only"):
        Model.train(X, y, lab, "yang208", "forest", n_trees=5).save(tmp_path / "f.npz")
    assert not (tmp_path / "f.npz").exists()


def test_protocol_passes_cover_groups():
    rng = np.random.default_rng(0)
    n = 30
    base = rng.normal(size=(n, 6)) * 3  # cover content dominates, the mark is a small shift
    X = np.vstack([base, base + [0.8, 0, 0, 0, 0, 0]])
    ds = {"cover": np.r_[np.arange(n), np.arange(n)], "method": np.array(["cover"] * n + ["m"] * n, dtype=object),
          "path": [f"c{i}" for i in range(n)], "X": {"yang208": X}, "failed": []}
    seen = []

    class Spy(clf.LogReg):
        def fit(self, X, y, groups=None):
            seen.append(groups)
            return super().fit(X, y, groups)
    clf.CLASSIFIERS["spy"] = Spy
    try:
        rows = P.evaluate(ds, "yang208", "spy", n_splits=2, universal="all")
    finally:
        del clf.CLASSIFIERS["spy"]
    assert all(g is not None and len(g) == 2 * len(set(g)) for g in seen)  # each cover with its stego row
    assert {r["detector"] for r in rows} == {"specific:m", "universal"}


def test_stacked_universal_learns_which_specific_detector_to_trust():
    """Two methods that shift different features: each specific detector sees only its own; the stacked
    universal detector (out-of-fold specific probabilities -> logistic regression) detects both, and its
    balanced error is far below a coin's."""
    rng = np.random.default_rng(3)
    n = 80
    base = rng.normal(size=(n, 4))
    X = np.vstack([base, base + [3.5, 0, 0, 0], base + [0, 0, 3.5, 0]])  # Bayes P_E of each: Phi(-1.75) = 0.04
    ds = {"cover": np.tile(np.arange(n), 3), "method": np.array(["cover"] * n + ["a"] * n + ["b"] * n, dtype=object),
          "path": [f"c{i}" for i in range(n)], "X": {"yang208": X}, "failed": []}
    rows = P.evaluate(ds, "yang208", "logreg", n_splits=3, universal="stack", C=1.0)
    u = [r for r in rows if r["detector"] == "universal"]
    assert len(u) == 3 and np.median([r["pe"] for r in u]) < 0.12
    assert all(r["n_train"] == 3 * (n - round(0.3 * n)) for r in u)  # every stego version of the training covers
    spec = [r for r in rows if r["detector"] == "specific:a"]
    assert np.median([r["accuracy"] for r in spec]) > 0.85
