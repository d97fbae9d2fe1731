"""meshmark.study method kinds: the thesis' raw-bits uses (cho-*-bits, radial-bits) give what the direct
API calls give for the same seed, and a kind registered from a plugin module runs in pool workers.
Reads ../shared/meshes (fails if missing)."""
import pathlib
import sys
import textwrap

import numpy as np
import pytest

from meshmark import MeshError, attacks as A
from meshmark.metrics import correlation, false_alarm_probability
from meshmark.study import Store, embed_key, load_results, load_spec, run
from meshmark.study.kinds import radial_capacity
from meshmark.study.task import load_mesh
from meshmark.watermark import cho, radial

from conftest import shared_mesh


def _rows(out):
    return {(r["method"], r["attack"], r["seed"]): r for r in load_results(out).to_pylist()}


def test_cho_bits_task_equals_the_direct_api(tmp_path):
    bunny = str(shared_mesh("classic/bunny.obj"))
    spec = {"study": {"seeds": [0, 3], "store": True},
            "meshes": {"paths": [bunny], "compact": True},
            "methods": [{"name": "cho-mean-bits", "label": "cm"},
                        {"name": "cho-variance-bits", "params": {"n_bits": 32}, "label": "cv"}],
            "attacks": [{"name": "none"}, {"name": "noise", "params": {"strength": 0.005}, "label": "noise"}],
            "measurements": ["nc", "cdr", "correlation", "detection", "message", "capacity", "carried", "rmse"]}
    S = run(spec, tmp_path / "out", workers=0, progress=False)
    assert S.ok == 8 and S.failed == 0
    rows = _rows(tmp_path / "out")
    m = load_mesh(bunny, None, True)
    sp = load_spec(spec)
    store = Store(tmp_path / "out" / "store")
    for label, kind, n in (("cm", "mean", 64), ("cv", "variance", 32)):
        for seed in (0, 3):
            bits = np.random.default_rng(seed).integers(0, 2, n)
            Vm, info = cho.embed_bits(m.V, m.triangles, bits, method=kind)
            # the stored marked mesh is the direct embedding, bit for bit
            mv = next(v for v in sp.methods if v.label == label)
            hit = store.get(embed_key(rows[(label, "none", seed)]["mesh_digest"], mv, seed, sp))
            assert np.array_equal(hit.mesh.V, Vm) and hit.meta["bits"] == bits.tolist()
            clean = rows[(label, "none", seed)]
            assert clean["cdr"] == 1.0 and clean["correlation"] == 1.0 and clean["message_ok"] and clean["carried"]
            assert clean["capacity"] == n and clean["payload_bits"] == n and clean["n_bits"] == n
            assert clean["detected"] == (0.5 ** n < 1e-6)
            rmse = np.sqrt(np.mean(np.sum((Vm - m.V) ** 2, axis=1))) / np.linalg.norm(m.V.max(0) - m.V.min(0))
            assert clean["embed_rmse_rel"] == pytest.approx(rmse, rel=1e-12)
            got = cho.extract_bits(A.noise(Vm, m.triangles, strength=0.005, seed=seed).V, m.triangles, n,
                                   method=kind)[0]
            r = rows[(label, "noise", seed)]
            assert r["correlation"] == correlation(bits, got)
            assert r["cdr"] == np.mean(got == bits) and r["matches"] == int((got == bits).sum())
            assert r["nc"] == pytest.approx(2 * r["cdr"] - 1, abs=1e-12)
            assert r["message_ok"] == bool(np.array_equal(got, bits))
            m_ = int((got == bits).sum())
            assert r["p_false_alarm"] == false_alarm_probability(m_, n) and r["detected"] == (r["p_false_alarm"] < 1e-6)
    # 0.5 % noise is not free: at least one of the four marks lost bits (the figures are not trivial)
    assert min(rows[(lab, "noise", s)]["cdr"] for lab in ("cm", "cv") for s in (0, 3)) < 1.0


def test_radial_bits_all_pairs_equals_the_direct_api(tmp_path):
    cow = str(shared_mesh("classic/cow.obj"))
    spec = {"study": {"seeds": [1]}, "meshes": {"paths": [cow], "compact": True},
            "methods": [{"name": "radial-bits", "params": {"n_bits": "all"}, "label": "yang"}],
            "attacks": [{"name": "none"}, {"name": "smooth", "params": {"lam": 0.02, "iterations": 10}, "label": "s"}],
            "measurements": ["correlation", "cdr", "capacity", "carried"]}
    run(spec, tmp_path / "out", workers=0, progress=False)
    rows = _rows(tmp_path / "out")
    m = load_mesh(cow, None, True)
    n = radial_capacity(m.V, m.triangles, 400)
    assert n == 191  # docs/radial.md: the Cow's embeddable pairs at K = 400
    bits = np.random.default_rng(1).integers(0, 2, n)
    Vm, _ = radial.embed_bits(m.V, m.triangles, bits, K=400)
    for att, V in (("none", Vm), ("s", A.smooth(Vm, m.triangles, lam=0.02, iterations=10).V)):
        got = radial.extract_bits(V, m.triangles, n, K=400)[0]
        r = rows[("yang", att, 1)]
        assert r["status"] == "ok" and r["capacity"] == n and r["payload_bits"] == n
        assert r["correlation"] == correlation(bits, got) and r["cdr"] == np.mean(got == bits)
    # docs/radial.md: smoothing 10 its leaves C far below 1 on the Cow (mean 0.17 over 5 seeds)
    assert rows[("yang", "s", 1)]["correlation"] < 0.6


PLUGIN = textwrap.dedent('''
    """A toy kind for the tests: QIM of the first n_bits x coordinates, step delta x bbox diagonal."""
    import numpy as np
    from meshmark.study import Marked, Read, register_method_kind

    def _step(mesh, p):
        return p["delta"] * float(np.linalg.norm(mesh.V.max(0) - mesh.V.min(0)))

    def embed(mesh, p, seed, spec):
        bits = np.random.default_rng(seed + 1000).integers(0, 2, p["n_bits"])
        d = _step(mesh, p)
        V = mesh.V.copy()
        x = V[: len(bits), 0]
        V[: len(bits), 0] = (np.round((x - bits * d / 2) / d) * d) + bits * d / 2
        return Marked(V=V, bits=bits, capacity=len(V), carried=True, info={"step": d})

    def extract(mesh, marked, p):
        d = marked.info["step"]
        got = np.round(mesh.V[: len(marked.bits), 0] / (d / 2)).astype(np.int64) % 2
        return Read.compare(marked.bits, got)

    register_method_kind("qim-x", defaults={"n_bits": 48, "delta": 1e-3}, embed=embed, extract=extract)
''')


def test_a_kind_registered_by_a_plugin_runs_in_pool_workers(tmp_path, monkeypatch):
    (tmp_path / "qim_plugin_for_tests.py").write_text(PLUGIN)
    monkeypatch.syspath_prepend(str(tmp_path))  # spawned workers get the driver's sys.path
    cow = shared_mesh("classic/cow.obj")
    spec = tmp_path / "qim.toml"
    spec.write_text(f'[study]\nplugins = ["qim_plugin_for_tests"]\nseeds = [0]\n[meshes]\npaths = ["{cow}"]\n'
                    '[[methods]]\nname = "qim-x"\ngrid = { delta = [1e-3, 1e-5] }\n'
                    '[[attacks]]\nname = "none"\n[[attacks]]\nname = "noise"\nparams = { strength = 0.0005 }\nlabel = "n"\n'
                    '[measurements]\nlist = ["cdr", "detection", "message", "capacity", "carried"]\n')
    S = run(spec, tmp_path / "out", workers=1, progress=False)
    assert S.ok == 4 and S.failed == 0
    rows = {(r["method"], r["attack"]): r for r in load_results(tmp_path / "out").to_pylist()}
    assert all(r["worker"].split(":")[1] != str(__import__("os").getpid()) for r in rows.values())
    for d in ("0.001", "1e-05"):
        clean = rows[(f"qim-x delta={d}", "none")]
        assert clean["cdr"] == 1.0 and clean["message_ok"] and clean["detected"] and clean["payload_bits"] == 48
    # 0.05 % noise: a 1e-3 step keeps every bit, a 1e-5 step loses about half
    assert rows[("qim-x delta=0.001", "n")]["cdr"] == 1.0
    assert 0.25 < rows[("qim-x delta=1e-05", "n")]["cdr"] < 0.75
    # an unknown parameter of the plugin's kind names the TOML line
    bad = tmp_path / "bad.toml"
    bad.write_text(spec.read_text().replace("grid = { delta", "grid = { delat"))
    with pytest.raises(MeshError, match=r"bad.toml:8: .*unknown parameter 'delat' for the qim-x method"):
        load_spec(bad)
    sys.modules.pop("qim_plugin_for_tests", None)


def test_bad_kind_parameters_and_plugins_name_their_lines(tmp_path):
    cow = shared_mesh("classic/cow.obj")
    head = f'[meshes]\npaths = ["{cow}"]\n'

    def err(body):
        p = tmp_path / "bad.toml"
        p.write_text(head + body)
        with pytest.raises(MeshError) as e:
            load_spec(p)
        return str(e.value)

    assert "bad.toml:5:" in (m := err('[[methods]]\nname = "cho-mean-bits"\nparams = { n_bits = "all" }\n')) \
        and "for radial-bits" in m
    assert "bad.toml:5:" in (m := err('[[methods]]\nname = "radial-bits"\nparams = { n_bits = 63, message = "balanced" }\n')) \
        and "even n_bits" in m
    assert "bad.toml:5:" in (m := err('[[methods]]\nname = "radial-bits"\ngrid = { n_thr = [3], Kk = [400] }\n')) \
        and "unknown parameter 'Kk'" in m
    m = err('[study]\nplugins = ["no_such_module_xyz"]\n')
    assert "bad.toml:4: study.plugins" in m and "no_such_module_xyz" in m


def test_plot_writes_the_figures_of_the_new_specs(tmp_path):
    import csv
    from meshmark.study.plot import plot
    bunny = str(shared_mesh("classic/bunny.obj"))
    spec = {"meshes": {"paths": [bunny], "compact": True}, "methods": [{"name": "cho-mean-bits", "label": "cm"}],
            "attacks": [{"name": "noise", "grid": {"strength": [0.001, 0.005]}}],
            "measurements": ["correlation", "cdr", "capacity"]}
    run(spec, tmp_path / "a", workers=0, progress=False)
    files = {pathlib.Path(f).name for f in plot(tmp_path / "a", tmp_path / "pa")}
    assert {"summary.csv", "cdr_vs_strength.png", "correlation_vs_strength.png", "capacity_vs_size.png"} <= files
    rows = {r["attack"]: r for r in load_results(tmp_path / "a").to_pylist()}
    summ = {r["attack"]: r for r in csv.DictReader(open(tmp_path / "pa" / "summary.csv"))}
    for att, r in rows.items():  # one seed: the summary's mean is the row's value
        assert float(summ[att]["correlation"]) == r["correlation"]
    # attack-only grid: the distortion figure, and the RMSE grows with the noise strength
    run({"meshes": {"paths": ["builtin:torus"]}, "attacks": [{"name": "noise", "grid": {"strength": [0.001, 0.004]}}],
         "measurements": ["rmse"]}, tmp_path / "b", workers=0, progress=False)
    files = {pathlib.Path(f).name for f in plot(tmp_path / "b", tmp_path / "pb")}
    assert "distortion_vs_strength.png" in files
    rm = {r["attack_level"]: r["rmse_rel"] for r in load_results(tmp_path / "b").to_pylist()}
    assert rm[0.004] == pytest.approx(4 * rm[0.001], rel=1e-9)  # the same seed: the noise scales linearly
