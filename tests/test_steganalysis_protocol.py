"""The ch. 8 protocol: registry, dataset, cover-level splits, P_E tables."""
import numpy as np
import pytest

import meshmark
import meshmark.attacks
from meshmark import MeshError
from meshmark.steganalysis import protocol as P
from conftest import shared_mesh


def test_splits_keep_a_cover_and_its_stego_together():
    cover = np.repeat(np.arange(20), 4)
    for tr, te in P.splits(20, 30, 0.3, seed=1):
        assert te.sum() == 6 and not (tr & te).any()
        side = te[cover]
        for c in range(20):
            assert len(set(side[cover == c])) == 1


def test_rates():
    r = P._rates([1, 1, 0, 0], [1, 0, 0, 1])
    assert r == {"accuracy": 0.5, "tpr": 0.5, "fpr": 0.5, "pe": 0.5}


def test_registry_dataset_and_evaluate():
    calls = []

    def shift(mesh, rng):  # a toy "stego method": noise of 5 % of the bounding box
        calls.append(1)
        ext = np.ptp(mesh.V, axis=0).max()
        return mesh.V + rng.normal(scale=0.05 * ext, size=mesh.V.shape)

    P.register_stego_method("toy-noise", shift, "5 % noise")
    try:
        paths = [shared_mesh(f"corpus/{n}") for n in (
            "vhacd_pig.off", "vhacd_eight.off", "vhacd_helix.off", "libigl_bumpy.off", "odedstein_fish_low_resolution.obj",
            "libigl_decimated-knight.off", "vhacd_block.off", "odedstein_torus.obj", "c3d_woody.obj", "vhacd_hornbug.off",
            "libigl_halftunnel.off", "odedstein_brucewick.obj", "odedstein_goathead.obj",
            "libigl_3holes.off")]
        with pytest.raises(MeshError, match="unknown stego method"):
            P.build_dataset(paths, ["nope"])
        ds = P.build_dataset(paths, ["toy-noise", "cho-variance"], ("yang208", "lfs76"))
        assert len(calls) == 14 and (ds["method"] == "cover").sum() == 14
        assert ds["X"]["yang208"].shape[1] == 208 and ds["X"]["lfs76"].shape[1] == 76
        assert P.dataset_features(ds, "yang208+lfs76").shape[1] == 284
        rows = P.evaluate(ds, "lfs76", "ensemble", n_splits=3, test_fraction=0.25, n_learners=11)
        toy = [r for r in rows if r["detector"] == "specific:toy-noise"]
        acc = [r["accuracy"] for r in toy]
        assert len(toy) == 3 and np.median(acc) >= 0.9 and min(acc) >= 0.75  # gross noise, 10 training covers
        tab = {r["detector"]: r for r in P.median_table(rows)}
        assert set(tab) == {"specific:toy-noise", "specific:cho-variance", "universal"}
        # universal training variants: the same test side (every test cover + one random stego version)
        for u in ("all", "max-specific"):
            ur = [r for r in P.evaluate(ds, "lfs76", "ensemble", n_splits=3, test_fraction=0.25, universal=u,
                                        n_learners=11) if r["detector"] == "universal"]
            pick = [r for r in rows if r["detector"] == "universal"]
            assert [r["n_test"] for r in ur] == [r["n_test"] for r in pick]
            if u == "all":  # every stego version of the training covers: more rows than one per cover
                assert all(r["n_train"] > p["n_train"] for r, p in zip(ur, pick))
        with pytest.raises(MeshError, match="universal must be one of"):
            P.evaluate(ds, "lfs76", universal="best")
        # leave one source out: 4 sources (v-hacd 4, libigl-tutorial-data 4, odedstein-meshes 5, common-3d-test-models 1)
        from meshmark.steganalysis import loso
        assert sorted(set(loso.cover_sources(ds))) == ["common-3d-test-models", "libigl-tutorial-data",
                                                        "odedstein-meshes", "v-hacd"]
        lr = loso.evaluate_by_source(ds, "lfs76", "ensemble", n_learners=11)
        toy = [r for r in lr if r["detector"] == "specific:toy-noise"]
        assert len(toy) == 4 and min(r["accuracy"] for r in toy) >= 0.75
        det = [r for r in lr if r["detector"] == "detects:toy-noise"]
        assert all(0 <= r["tpr"] <= 1 for r in det) and len(det) == 4
        tab = loso.source_table(lr)
        assert tab[-1]["source"].startswith("all") and tab[-1]["n_covers"] == 14
        # covers made in memory: (name, Mesh) pairs
        m = meshmark.read_mesh(paths[0])
        ds2 = P.build_dataset([("pig-patch", meshmark.attacks.crop(m, fraction=0.3))], ["cho-variance"])
        assert ds2["path"] == ["pig-patch"] and list(ds2["method"]) == ["cover", "cho-variance"]
    finally:
        del P.STEGO_METHODS["toy-noise"]


def test_bad_corpora(tmp_path):
    (tmp_path / "t.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(MeshError, match="empty training corpus.*too small"):
        P.build_dataset([tmp_path / "t.obj"], ["cho-mean"])
    with pytest.raises(MeshError, match="no such file"):
        P.mesh_files([tmp_path / "missing"])
    ds = P.build_dataset([shared_mesh("corpus/vhacd_pig.off")], ["cho-variance"])
    with pytest.raises(MeshError, match="at least 4 covers"):
        P.evaluate(ds, "yang208")


def test_subset():
    ds = {"cover": np.array([0, 0, 1, 1, 2]), "method": np.array(["cover", "a", "cover", "a", "cover"], dtype=object),
          "path": ["x/psb-seg/1.off", "y/2.off", "x/psb-seg/3.off"], "X": {"s": np.arange(5.0)[:, None]}}
    sub = P.subset(ds, "psb-seg")
    assert sub["cover"].tolist() == [0, 0, 1] and sub["X"]["s"].ravel().tolist() == [0, 1, 4]
    with pytest.raises(MeshError, match="no cover path"):
        P.subset(ds, "nope")


def test_stego_module_registration_with_the_api_of_main(monkeypatch):
    """LSB and Chao come from meshmark.stego (not on this branch): a stand-in with the signatures of
    main's stego.embed(mesh, message, key, tolerance) and stego.chao.embed(mesh, bits, fill, seed)."""
    import sys
    import types
    seen = []

    class R:
        def __init__(self, V):
            self.V = V

    def embed(mesh, message, key, tolerance=1.0, adaptive=True, precision="fixed32", levels=None):
        seen.append(("lsb", message, tolerance, bool(key)))
        return R(mesh.V + 1)

    def chao_embed(mesh, bits=None, *, message=None, n_layers=10, n_intervals=10000, fill=False, seed=None):
        seen.append(("chao", len(bits), fill, n_layers, n_intervals))
        return R(mesh.V + 2)

    fake = types.ModuleType("meshmark.stego")
    fake.embed, fake.chao = embed, types.SimpleNamespace(embed=chao_embed)
    monkeypatch.setitem(sys.modules, "meshmark.stego", fake)
    monkeypatch.setattr(meshmark, "stego", fake, raising=False)
    got = {}
    assert P._register_stego_module(lambda name, fn, text: got.__setitem__(name, fn))
    assert list(got) == ["lsb-1deg", "lsb-2deg", "lsb-5deg", "chao"]
    m = meshmark.read_mesh(shared_mesh("corpus/vhacd_pig.off"))
    rng = np.random.default_rng(0)
    assert np.array_equal(got["lsb-5deg"](m, rng), m.V + 1) and np.array_equal(got["chao"](m, rng), m.V + 2)
    assert seen == [("lsb", b"", 5.0, True), ("chao", 0, True, 10, 10000)]
