"""The shipped default steganalysis model on meshes that are not in ../shared (docs/steganalysis.md,
"Default model on unseen meshes"): generated hold-out covers, its operating point and its
out-of-distribution guard; the generators' families and reproducibility."""
import json
import subprocess
import sys

import numpy as np
import pytest

from meshmark import MeshError
from meshmark.steganalysis import generated as G
from meshmark.steganalysis import protocol as P
from meshmark.steganalysis.features import features
from meshmark.steganalysis.model import Model


def test_generators_are_reproducible_and_the_families_disjoint():
    assert not set(G.HOLDOUT_FAMILIES) & set(G.TRAINING_FAMILIES)
    a, b = G.holdout_covers(3, seed=5), G.holdout_covers(3, seed=5)
    for (na, ma), (nb, mb) in zip(a, b):
        assert na == nb and np.array_equal(ma.V, mb.V) and np.array_equal(ma.F, mb.F)
    assert not np.array_equal(G.holdout_covers(1, seed=6)[0][1].V[:5], a[0][1].V[:5])
    assert [n.split("#")[0] for n, _ in G.training_covers(3)] == list(G.TRAINING_FAMILIES)
    with pytest.raises(MeshError, match="training family"):
        G.holdout_covers(1, families=["icosphere"])
    with pytest.raises(MeshError, match="hold-out family"):
        G.training_covers(1, families=["hull-blob"])
    for _, m in G.holdout_covers(3, seed=1) + G.training_covers(3, seed=1):
        assert m.n_vertices >= 100 and np.isfinite(m.V).all()
        # closed meshes (all but the height field) are edge-manifold: every edge in exactly two triangles
        e = np.sort(np.concatenate([m.F[:, [0, 1]], m.F[:, [1, 2]], m.F[:, [2, 0]]]), axis=1)
        _, counts = np.unique(e, axis=0, return_counts=True)
        assert counts.max() <= 2


def test_threshold_and_guard_roundtrip(tmp_path):
    rng = np.random.default_rng(0)
    X = rng.normal(size=(80, 36))
    y = np.r_[np.zeros(40), np.ones(40)].astype(int)
    X[y == 1] += 1.0
    lab = np.where(y == 1, "a", "cover")
    m = Model.train(X, y, lab, "nvt36", "ensemble", n_learners=11)
    assert m.threshold == 0.5 and m.guard is None and "in_distribution" not in m.detect_features(X[0])
    m.threshold = 0.8
    m.set_guard(X, margin=0.1, max_outside=0.2)
    m.save(tmp_path / "m.npz")
    m2 = Model.load(tmp_path / "m.npz")
    assert m2.threshold == 0.8 and m2.guard["max_outside"] == 0.2
    far = X[0] + 100.0  # every feature outside the training range
    for mm in (m, m2):
        r = mm.detect_features(X[-1])
        assert r["in_distribution"] and r["marked"] == (r["probability"] > 0.8)
        r = mm.detect_features(far)
        assert not r["in_distribution"] and r["outside_fraction"] == 1.0 and not r["marked"]
        assert "cannot judge" in r["warning"]
        assert mm.detect_features(far, guard=False)["marked"] == (r["probability"] > 0.8)


def test_shipped_model_on_generated_holdout_meshes():
    """Fresh hold-out meshes (seed 123: not those of the documented measurement, never trained on).
    Measured with the model of format 3: 0 of 6 clean ones called marked; Cho variance at the §8.2
    strength and LSB at 5 degrees found on 0 of 12 marked versions (cross-validated detection 6.7 % at
    the 5 % operating point: at most a few of 12 are expected), and the universal probability of the
    marked version above that of its clean cover in 11 of 12 pairs: the ranking holds, the threshold is
    conservative."""
    model = Model.load()
    cal = model.training["calibration"]
    assert 0.5 < model.threshold < 1 and model.guard is None and cal["oof_fpr"] <= model.training["fpr_target"] == 0.05
    covers = G.holdout_covers(6, seed=123)
    clean = [model.detect(m) for _, m in covers]
    assert sum(r["marked"] for r in clean) <= 1, [(n, r["probability"]) for (n, _), r in zip(covers, clean)]
    hits, higher = 0, 0
    for j, (_, m) in enumerate(covers):
        for k, meth in enumerate(("cho-variance", "lsb-5deg")):
            V = P.STEGO_METHODS[meth][0](m, np.random.default_rng([5, j, k]))
            r = model.detect(m.with_vertices(V))
            hits += r["marked"]
            higher += r["probability"] > clean[j]["probability"]
    assert hits <= 6 and higher >= 9, (hits, higher)


def test_cli_detect_reports_the_operating_point(tmp_path):
    from meshmark.io import write_mesh
    _, m = G.holdout_covers(1, seed=3)[0]
    p = tmp_path / "h.obj"
    write_mesh(p, m.V, m.F)
    x = subprocess.run([sys.executable, "-m", "meshmark.cli", "steganalysis", "detect", str(p), "--json"],
                       capture_output=True, text=True)
    d = json.loads(x.stdout)
    assert x.returncode == (0 if d["detected"] else 1), x.stderr
    assert {"detected", "methods", "threshold", "operating_point"} <= set(d) and "in_distribution" not in d
    assert d["operating_point"]["cv_fpr"] <= 0.05 and d["threshold"] == Model.load().threshold
    assert len(d["methods"]) == 11 and all(0 <= v <= 1 for v in d["methods"].values())
    r = Model.load().detect_features(features(m, Model.load().feature_set))
    assert d["detected"] == r["marked"] and d["probability"] == r["probability"]
