"""Classifiers (eq. 8.1.5, QDA, Kodovský's FLD ensemble), model files and the train/detect CLI."""
import json
import subprocess
import sys

import numpy as np
import pytest
from sklearn.discriminant_analysis import LinearDiscriminantAnalysis, QuadraticDiscriminantAnalysis

from meshmark import MeshError
from meshmark.steganalysis import classifiers as clf
from meshmark.steganalysis.model import Model
from conftest import shared_mesh


def gaussian_data(n=300, d=6, shift=1.0, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(d, d))
    X0 = rng.normal(size=(n, d)) @ A
    X1 = rng.normal(size=(n, d)) @ (A * 1.3) + shift
    return np.vstack([X0, X1]), np.r_[np.zeros(n), np.ones(n)].astype(int)


def test_minmax_eq_8_1_5_uses_training_data_only():
    Xtr = np.array([[0.0, 5], [2, 5], [4, 5]])
    s = clf.MinMaxScaler().fit(Xtr)
    np.testing.assert_allclose(s.transform(Xtr)[:, 0], [0, 0.5, 1])
    np.testing.assert_allclose(s.transform([[8.0, 7]]), [[2.0, 2.0]])  # test data may leave [0, 1]; constant -> offset


def test_qda_matches_sklearn():
    X, y = gaussian_data()
    ours = clf.QDA(reg_param=0.05).fit(X, y)
    Z = clf.MinMaxScaler().fit(X).transform(X)
    sk = QuadraticDiscriminantAnalysis(reg_param=0.05).fit(Z, y)
    np.testing.assert_allclose(ours.predict_proba(X), sk.predict_proba(Z)[:, 1], atol=1e-6)
    # with PCA to k components: the same as sklearn's PCA -> QDA pipeline
    from sklearn.decomposition import PCA
    P = PCA(3, svd_solver="full").fit(Z)
    sk = QuadraticDiscriminantAnalysis(reg_param=0.1).fit(P.transform(Z), y)
    np.testing.assert_allclose(clf.QDA(n_components=3).fit(X, y).predict_proba(X),
                               sk.predict_proba(P.transform(Z))[:, 1], atol=1e-6)


def test_fld_is_fishers_direction_and_ensemble_votes():
    X, y = gaussian_data(d=5)
    w = clf._fld(X[y == 0], X[y == 1], 1e-12)
    lda = LinearDiscriminantAnalysis(solver="eigen").fit(X, y)
    cos = w @ lda.coef_[0] / np.linalg.norm(w) / np.linalg.norm(lda.coef_[0])
    assert cos == pytest.approx(1.0, abs=1e-8)
    Xa, ya = gaussian_data(n=400, d=40, shift=0.6, seed=1)
    tr = np.arange(len(ya)) % 2 == 0
    X, y, Xt, yt = Xa[tr], ya[tr], Xa[~tr], ya[~tr]
    e = clf.FLDEnsemble(n_learners=31, seed=3).fit(X, y)
    acc = ((e.predict_proba(Xt) > 0.5) == yt).mean()
    lda_acc = (LinearDiscriminantAnalysis().fit(X, y).predict(Xt) == yt).mean()
    assert acc > 0.9 and acc >= lda_acc - 0.05 and 0 <= e.oob_error < 0.15
    assert e.subsets.shape[0] == 31 and set(np.unique(e.predict_proba(Xt) * 31).round(6)) <= set(range(32))


def test_threshold_minimises_pe():
    t, pe = clf._best_threshold(np.array([0.0, 1, 2]), np.array([2.5, 3, 4]))
    assert 2 < t < 2.5 and pe == 0
    t, pe = clf._best_threshold(np.array([0.0, 1, 2, 5]), np.array([1.5, 3, 4, 6]))
    assert pe == pytest.approx(0.25)


def test_bad_training_input():
    with pytest.raises(MeshError, match="empty"):
        clf.FLDEnsemble().fit(np.zeros((0, 3)), [])
    with pytest.raises(MeshError, match="both covers and stego"):
        clf.QDA().fit(np.ones((5, 3)), np.zeros(5))
    with pytest.raises(MeshError, match="empty training corpus"):
        Model.train(np.zeros((0, 208)), [], [], "yang208")
    with pytest.raises(MeshError, match="both covers and stego"):  # a single class
        Model.train(np.ones((6, 208)), np.zeros(6), ["cover"] * 6, "yang208")


def test_model_roundtrip_and_version(tmp_path):
    X, y = gaussian_data(n=60, d=208, seed=4)
    lab = np.where(y == 1, np.where(np.arange(len(y)) % 2, "a", "b"), "cover")
    for kind in ("ensemble", "qda"):
        m = Model.train(X, y, lab, "yang208", kind, {"corpus_hash": "x"}, **({"n_learners": 11} if kind == "ensemble" else {}))
        p = tmp_path / f"{kind}.npz"
        m.save(p)
        m2 = Model.load(p)
        r1, r2 = m.detect_features(X[0]), m2.detect_features(X[0])
        assert r1 == r2 and set(r1["methods"]) == {"a", "b"} and m2.training["corpus_hash"] == "x"
    z = dict(np.load(tmp_path / "qda.npz"))
    meta = json.loads(bytes(z["meta"]).decode())
    meta["format_version"] = 99
    z["meta"] = np.frombuffer(json.dumps(meta).encode(), np.uint8)
    np.savez(tmp_path / "old.npz", **z)
    with pytest.raises(MeshError, match="format version 99"):
        Model.load(tmp_path / "old.npz")
    meta["format_version"] = 2  # models before the stabilised features (issue 25): features that no longer exist
    z["meta"] = np.frombuffer(json.dumps(meta).encode(), np.uint8)
    np.savez(tmp_path / "v2.npz", **z)
    with pytest.raises(MeshError, match="format version 2; this meshmark reads version 3: retrain"):
        Model.load(tmp_path / "v2.npz")
    meta["format_version"], meta["features_version"] = 3, 2
    z["meta"] = np.frombuffer(json.dumps(meta).encode(), np.uint8)
    np.savez(tmp_path / "f2.npz", **z)
    with pytest.raises(MeshError, match="features version 2.*retrain"):
        Model.load(tmp_path / "f2.npz")


def test_domain_check_verdicts(tmp_path):
    """A mesh far from the training covers is 'cannot judge' (the verdict field), whatever its probability;
    the threshold is calibrated so that `rate` of the covers, each against the other groups, lie beyond it."""
    X, y = gaussian_data(n=80, d=36, seed=5)
    lab = np.where(y == 1, "a", "cover")
    m = Model.train(X, y, lab, "nvt36s", "ensemble", n_learners=11)
    c = y == 0
    info = m.set_domain(X[c], np.arange(int(c.sum())) // 2, rate=0.1)
    assert 0.05 <= info["flagged"] <= 0.15
    m.save(tmp_path / "m.npz")
    m2 = Model.load(tmp_path / "m.npz")
    for mm in (m, m2):
        r = mm.detect_features(X[0])
        assert r["in_domain"] and r["verdict"] in ("marked", "no evidence") and r["reason"] is None
        assert r["verdict"] == ("marked" if r["probability"] > mm.threshold else "no evidence")
        r = mm.detect_features(X[0] + 50 * (X.max(0) - X.min(0)))
        assert not r["in_domain"] and r["verdict"] == "cannot judge" and not r["marked"] and "cannot judge" in r["reason"]
        assert r["domain_distance"] > r["domain_threshold"] == mm.domain["threshold"]
    (tmp_path / "junk.npz").write_bytes(b"not a model")
    with pytest.raises(MeshError, match="not a meshmark steganalysis model"):
        Model.load(tmp_path / "junk.npz")
    with pytest.raises(MeshError, match="does not exist"):
        Model.load(tmp_path / "missing.npz")


def run(*a):
    return subprocess.run([sys.executable, "-m", "meshmark.cli", "steganalysis", *a], capture_output=True, text=True)


def test_cli_features_and_bad_input(tmp_path):
    x = run("features", str(shared_mesh("classic/cow.obj")), "--set", "yang208", "--json")
    d = json.loads(x.stdout)
    assert x.returncode == 0 and len(d["features"]) == 208
    tiny = tmp_path / "tri.obj"
    tiny.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    x = run("features", str(tiny), "--json")
    assert x.returncode == 2 and "too small" in x.stderr
    x = run("detect", str(tiny), "--json")  # a verdict, not an error: the detector cannot judge it
    d = json.loads(x.stdout)
    assert x.returncode == 1 and d["verdict"] == "cannot judge" and "too small" in d["reason"] and d["detected"] is False
    # issue 23: a bad --out fails before any training (checked first in train_cmd: no "[1/1]" feature work)
    x = run("train", str(shared_mesh("classic/cow.obj")), "--out", str(tmp_path / "nope" / "m.npz"))
    assert x.returncode == 2 and "does not exist" in x.stderr
    x = run("train", str(shared_mesh("classic/cow.obj")), "--out", str(tmp_path))
    assert x.returncode == 2 and "is a folder" in x.stderr
    (tmp_path / "empty").mkdir()
    x = run("train", str(tmp_path / "empty"), "--out", str(tmp_path / "m.npz"))
    assert x.returncode == 2 and "empty training corpus" in x.stderr and not (tmp_path / "m.npz").exists()
    x = run("train", str(shared_mesh("classic/cow.obj")), "--methods", "none", "--out", str(tmp_path / "m.npz"))
    assert x.returncode == 2 and "both covers and stego" in x.stderr and not (tmp_path / "m.npz").exists()
    x = run("detect", str(shared_mesh("classic/cow.obj")), "--model", str(tmp_path / "nope.npz"))
    assert x.returncode == 2 and "does not exist" in x.stderr


def test_cli_train_detect_evaluate(tmp_path):
    import shutil
    covers = tmp_path / "covers"
    covers.mkdir()
    for n in ("vhacd_pig.off", "vhacd_eight.off", "libigl_bumpy.off", "odedstein_fish_low_resolution.obj",
              "libigl_decimated-knight.off", "vhacd_block.off", "odedstein_torus.obj", "vhacd_helix.off"):
        shutil.copy(shared_mesh(f"corpus/{n}"), covers / n)
    model = tmp_path / "m.npz"
    x = run("train", str(covers), "--out", str(model), "--set", "lfs76", "--methods", "cho-variance,radial", "--json")
    d = json.loads(x.stdout)
    assert x.returncode == 0, x.stderr
    assert d["n_covers"] == 8 and d["methods"] == ["cho-variance", "radial"] and len(d["corpus_hash"]) == 64
    x = run("detect", str(covers / "vhacd_pig.off"), "--model", str(model), "--json")
    d = json.loads(x.stdout)
    # a clean training cover: not marked, exit 1
    assert (x.returncode, d["detected"], set(d["methods"])) == (1, False, {"cho-variance", "radial"}), x.stderr
    # the same cover Cho-variance marked (alpha 0.16): marked, exit 0
    import meshmark
    from meshmark.watermark import cho
    pig = meshmark.read_mesh(covers / "vhacd_pig.off")
    meshmark.write_mesh(tmp_path / "pig_marked.off", cho.embed(pig, payload="x", key="k", method="variance").V, pig)
    x = run("detect", str(tmp_path / "pig_marked.off"), "--model", str(model), "--json")
    d = json.loads(x.stdout)
    assert (x.returncode, d["detected"]) == (0, True), x.stdout
    x = run("evaluate", str(covers), "--set", "lfs76", "--methods", "cho-variance", "--splits", "2",
            "--dataset", str(tmp_path / "ds.npz"), "--csv", str(tmp_path / "rows.csv"), "--json")
    d = json.loads(x.stdout)
    assert x.returncode == 0, x.stderr
    assert {r["detector"] for r in d["table"]} == {"specific:cho-variance", "universal"}
    assert (tmp_path / "ds.npz").is_file() and len((tmp_path / "rows.csv").read_text().splitlines()) == 5
    # issue 23: a cache built for other covers / methods / sets is refused, never reused silently
    x = run("evaluate", str(covers), "--set", "nvt36", "--dataset", str(tmp_path / "ds.npz"))
    assert x.returncode == 2 and "other covers" in x.stderr
    (covers / "vhacd_helix.off").unlink()
    x = run("evaluate", str(covers), "--set", "lfs76", "--methods", "cho-variance", "--splits", "2",
            "--dataset", str(tmp_path / "ds.npz"))
    assert x.returncode == 2 and "other covers" in x.stderr
    x = run("detect", str(covers / "vhacd_pig.off"), "--json")  # the shipped default model
    d = json.loads(x.stdout)
    # a clean cover: probability ~0.71 against the threshold 0.990, in the model's domain -> exit 1
    assert x.returncode == 1 and "cho-mean" in d["methods"] and d["feature_set"] == "yang208+lfs76s+nvt36s"
    assert (d["verdict"], d["detected"], d["in_domain"]) == ("no evidence", False, True)
    assert d["probability"] < d["threshold"] - 0.1
