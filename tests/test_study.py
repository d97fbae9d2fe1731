"""meshmark.study: spec validation (errors name the TOML line), keys, the store, identical results with
1 / 2 workers and Dask, resume after SIGKILL. The smoke spec reads ../shared/meshes (fails if missing)."""
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pyarrow.parquet as pq
import pytest

import meshmark
from meshmark import MeshError
from meshmark.study import Store, embed_key, load_results, load_spec, plan, run
from meshmark.study.engine import finished_keys

from conftest import shared_mesh

ROOT = pathlib.Path(__file__).resolve().parents[1]
SMOKE = ROOT / "examples" / "studies" / "smoke.toml"
MESHMARK = str(pathlib.Path(sys.executable).parent / "meshmark")


def _spec_text(body: str) -> str:
    cow = shared_mesh("classic/cow.obj")
    return f'[meshes]\npaths = ["{cow}"]\n' + body


def _error(tmp_path, text):
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(MeshError) as e:
        load_spec(p)
    return str(e.value)


# --- bad specs: a clear error naming the line, before any task runs ---------------------------------

def test_unknown_method_names_its_line(tmp_path):
    msg = _error(tmp_path, _spec_text('\n[[methods]]\nname = "laplacian"\n\n[[methods]]\nname = "lapalcian"\n'))
    assert "bad.toml:8:" in msg and "unknown method 'lapalcian'" in msg and "cho-mean" in msg


def test_unknown_attack_and_parameters_name_their_lines(tmp_path):
    msg = _error(tmp_path, _spec_text('[[attacks]]\nname = "noise"\ngrid = { strength = [0.001] }\n'
                                      '[[attacks]]\nname = "blur"\n'))
    assert "bad.toml:7:" in msg and "unknown attack 'blur'" in msg
    msg = _error(tmp_path, _spec_text('[[methods]]\nname = "cho-mean"\n[methods.params]\nK = 32\nalfa = 0.03\n'))
    assert "bad.toml:7:" in msg and "unknown parameter 'alfa'" in msg and "alpha" in msg
    msg = _error(tmp_path, _spec_text('[[attacks]]\nname = "smooth"\ngrid = { iterations = [10], lamda = [0.1] }\n'))
    assert "bad.toml:5:" in msg and "unknown parameter 'lamda'" in msg
    # a bad value is caught too, by running the attack once on a tiny mesh at planning time
    msg = _error(tmp_path, _spec_text('[[attacks]]\nname = "noise"\nparams = { strength = -1.0 }\n'))
    assert "bad.toml:5:" in msg and "noise strength must be >= 0" in msg


def test_range_min_above_max_and_empty_mesh_set(tmp_path):
    msg = _error(tmp_path, _spec_text('[[methods]]\nname = "cho-mean"\nrandom = { alpha = [0.06, 0.02] }\ndraws = 3\n'))
    assert "bad.toml:5:" in msg and "min > max" in msg
    msg = _error(tmp_path, f'[study]\nseeds = 2\n\n[meshes]\npaths = ["{tmp_path}/*.obj"]\n')
    assert "bad.toml:5:" in msg and "matches no mesh file" in msg
    (tmp_path / "sub").mkdir()
    msg = _error(tmp_path, f'[meshes]\npaths = ["{tmp_path}/sub"]\n')
    assert "bad.toml:2:" in msg and "matches no mesh file" in msg
    with pytest.raises(MeshError, match=r"methods\[0\]\.name: unknown method"):  # a dict names the key path
        load_spec({"meshes": [str(shared_mesh("classic/cow.obj"))], "methods": [{"name": "nope"}]})


def test_grid_and_random_draws_expand_deterministically():
    d = {"meshes": [str(shared_mesh("classic/cow.obj"))],
         "methods": [{"name": "cho-mean", "grid": {"K": [32, 64]}, "random": {"alpha": [0.02, 0.06]}, "draws": 3}],
         "attacks": [{"name": "noise", "grid": {"strength": [0.001, 0.002]}},
                     {"chain": [{"name": "smooth", "params": {"iterations": 5}}, {"name": "float32"}]}],
         "study": {"seeds": 2}}
    s = load_spec(d)
    assert len(s.methods) == 6 and len(s.attacks) == 3 and s.n_tasks == 36
    alphas = [m.params["alpha"] for m in s.methods]
    assert all(0.02 <= a <= 0.06 for a in alphas) and len(set(alphas)) == 6
    assert [m.params for m in load_spec(d).methods] == [m.params for m in s.methods]
    k1, idx, _ = plan(s)
    assert len(set(k1)) == 36 and idx.shape == (36, 4)
    # keys are a function of the task's inputs: adding an attack keeps every existing key
    d2 = {**d, "attacks": d["attacks"] + [{"name": "quantize", "params": {"bits": 9}}]}
    k2, _, _ = plan(load_spec(d2))
    assert set(k1) < set(k2) and len(k2) == 48


# --- the store --------------------------------------------------------------------------------------

def test_store_put_get_roundtrip(tmp_path):
    m = meshmark.read_mesh(shared_mesh("classic/suzanne.obj"))  # quads and triangles
    st = Store(tmp_path / "store")
    d1 = st.put("k1", m, note="x")
    d2 = st.put("k2", m)
    assert d1 == d2 and len(list((tmp_path / "store" / "objects").rglob("*.npz"))) == 1  # content-addressed
    hit = st.get("k1")
    assert hit.meta == {"note": "x"} and hit.digest == d1
    assert np.array_equal(hit.mesh.V, m.V) and np.array_equal(hit.mesh.face_offsets, m.face_offsets)
    assert np.array_equal(hit.mesh.face_indices, m.face_indices)
    assert st.get(d1) is not None and st.get("missing") is None and "k2" in st


# --- runs: identical with 1 / 2 workers and Dask; resume after SIGKILL -------------------------------

@pytest.fixture(scope="module")
def reference_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("study") / "w1"
    r = subprocess.run([MESHMARK, "study", "run", str(SMOKE), "--out", str(out), "--workers", "1"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return out


def _same(a, b):
    ta, tb = load_results(a, volatile=False), load_results(b, volatile=False)
    assert ta.column_names == tb.column_names
    assert ta.num_rows == tb.num_rows
    for c in ta.column_names:
        assert ta.column(c).equals(tb.column(c)), c


def test_smoke_results_are_real(reference_run):
    rows = load_results(reference_run).to_pylist()
    assert len(rows) == load_spec(SMOKE).n_tasks == 240
    st = [r["status"] for r in rows]
    # 136 ok: the torus offers 18 (Laplacian) and 22 (Cho) carriers, too few for one bit with the 20 check
    # bits of the keyed-check code (32 needed), and its radial mark does not take: recorded mesh errors
    assert st.count("error") == 0 and st.count("ok") >= 136
    by = {(r["mesh"], r["method_name"], r["attack"], r["seed"]): r for r in rows}
    # no attack: the mark reads back exactly; attack-only rows: zero distortion
    for mesh in ("classic/fandisk.obj", "builtin:torus"):
        r = by[(mesh, "laplacian", "none", 0)]
        if mesh == "builtin:torus":  # at most 23 Laplacian carriers: too few for one coded bit (32 needed)
            assert r["status"] == "mesh_error" and "too few for one payload bit" in r["error"]
        else:
            assert r["status"] == "ok" and r["cdr"] == 1.0 and r["nc"] == 1.0 and r["message_ok"]
        a = by[(mesh, "none", "none", 0)]
        assert a["rmse_rel"] == 0.0 and a["nc"] is None and a["embed_rmse_rel"] is None
    # suzanne offers 2 Laplacian carriers at the published parameters; the automatic choice finds enough
    r = by[("classic/suzanne.obj", "laplacian", "none", 0)]
    assert r["status"] == "ok" and r["cdr"] == 1.0 and r["message_ok"]
    # the raw-bits kind: a balanced 32-bit message, read back exactly on the fandisk with no attack
    r = by[("classic/fandisk.obj", "cho-mean-bits", "none", 1)]
    assert r["status"] == "ok" and r["cdr"] == 1.0 and r["correlation"] == 1.0 and r["carried"]
    assert r["payload_bits"] == 32 and r["nc"] is not None and by[("classic/fandisk.obj", "laplacian", "none", 0)]["correlation"] is None
    # the seed changes the payload and the noise; reordering keeps the distortion at zero after undo-free
    # measurement only when the vertices correspond: RMSE is null for it (faces re-indexed)
    assert by[("classic/fandisk.obj", "none", "reorder", 0)]["rmse_rel"] is None
    n0, n1 = (by[("classic/fandisk.obj", "none", "noise strength=0.001", s)]["rmse_rel"] for s in (0, 1))
    assert n0 != n1 and 1e-4 < n0 < 1e-3
    # the store holds one marked mesh per (mesh, method, seed) that took the mark, reusable by key
    sp = load_spec(SMOKE)
    keys = set(Store(reference_run / "store").keys())
    dig = {lab: r["mesh_digest"] for (lab, *_), r in by.items()}
    mv = next(m for m in sp.methods if m.name == "laplacian")
    ek = embed_key(dig["classic/fandisk.obj"], mv, 0, sp)
    assert ek in keys
    hit = Store(reference_run / "store").get(ek)
    m = meshmark.read_mesh(shared_mesh("classic/fandisk.obj"))
    x = meshmark.watermark.extract(hit.mesh, keyfile=meshmark.watermark.Keyfile.from_dict(hit.meta["keyfile"]))
    assert x.cdr == 1.0 and hit.mesh.n_vertices == m.n_vertices


def test_identical_results_workers_2_and_dask(reference_run, tmp_path):
    run(SMOKE, tmp_path / "w2", workers=2, progress=False)
    _same(reference_run, tmp_path / "w2")
    pytest.importorskip("distributed")
    run(SMOKE, tmp_path / "dask", dask="local:2", progress=False)
    _same(reference_run, tmp_path / "dask")


def test_resume_after_sigkill(reference_run, tmp_path):
    out = tmp_path / "killed"
    p = subprocess.Popen([MESHMARK, "study", "run", str(SMOKE), "--out", str(out), "--workers", "2",
                          "--chunk-size", "8", "--no-progress"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                         start_new_session=True)
    try:
        t0 = time.monotonic()
        while len(list((out / "results").glob("part-*.parquet"))) < 4:
            assert p.poll() is None, "the run ended before it could be killed"
            assert time.monotonic() - t0 < 240
            time.sleep(0.05)
    finally:
        os.killpg(p.pid, signal.SIGKILL)  # the driver and its worker processes
        p.wait()
    before = finished_keys(out)
    n_parts = len(list((out / "results").glob("part-*.parquet")))
    assert 0 < len(before) < 240
    S = run(SMOKE, out, workers=2, progress=False)
    assert S.skipped == len(before) and S.ran == 240 - len(before)
    # no finished task was run again: every key is in exactly one row over all partitions
    keys = [k for f in sorted((out / "results").glob("part-*.parquet")) for k in pq.read_table(f).column("key").to_pylist()]
    assert len(keys) == len(set(keys)) == 240 and n_parts < len(list((out / "results").glob("part-*.parquet")))
    _same(reference_run, out)


def test_failed_task_is_recorded_retried_once_and_reported(tmp_path):
    import pyarrow as pa
    from meshmark.study import register_measurement
    from meshmark.study.measure import MEASUREMENTS
    calls = []

    @register_measurement("boom_for_test", {"boom": pa.int64()})
    def _boom(ctx):
        calls.append(ctx.attacked.n_vertices)
        if ctx.attacked.n_vertices == ctx.original.n_vertices:  # fails for the unattacked task only
            raise RuntimeError("boom")
        return {"boom": 1}

    try:
        spec = {"meshes": [str(shared_mesh("classic/suzanne.obj"))],
                "attacks": ["none", {"name": "subdivide", "params": {"scheme": "midpoint"}}],
                "measurements": ["rmse", "boom_for_test"]}
        S = run(spec, tmp_path / "out", workers=0, progress=False)  # in-process: the registry is this one
    finally:
        del MEASUREMENTS["boom_for_test"]
    assert (S.ok, S.failed, S.retried) == (1, 1, 1) and "RuntimeError: boom" in S.failures[0]["error"]
    assert len(calls) == 3  # the failing task ran twice, the other once
    rows = [r for f in sorted((tmp_path / "out" / "results").glob("part-*.parquet")) for r in pq.read_table(f).to_pylist()]
    failed = sorted((r["attempt"], r["status"]) for r in rows if r["attack"] == "none")
    assert failed == [(1, "error"), (2, "error")]
    t = load_results(tmp_path / "out").to_pylist()
    assert sorted((r["attack"], r["status"], r["boom"]) for r in t) == [("none", "error", None), ("subdivide", "ok", 1)]


def test_bend_is_the_laplacian_tests_skinning():
    """blender_bend is tested with bpy in blender_tests/test_study_blender.py."""
    from test_laplacian_watermark import bend as reference_bend, jittered_arm
    from meshmark.attacks import bend
    from meshmark.study.task import builtin_mesh
    arm = builtin_mesh("arm")
    assert np.array_equal(arm.V, jittered_arm().V)
    for deg in (0, 30, 60):
        out = bend(arm, degrees=deg, joint=1.0, width=0.2, absolute=True)
        assert np.array_equal(out.V, reference_bend(arm.V, deg))
    # relative joint: the middle of the z extent with a tenth of it as the blend width, the joint
    # line through the middle of the y extent (0 once the arm is centred in y)
    lo, hi = arm.V[:, 2].min(), arm.V[:, 2].max()
    ymid = (arm.V[:, 1].min() + arm.V[:, 1].max()) / 2
    Vc = arm.V - [0, ymid, 0]
    assert np.allclose(bend(arm.with_vertices(Vc), degrees=45).V, reference_bend(Vc, 45, (lo + hi) / 2, 0.1 * (hi - lo)),
                       rtol=0, atol=1e-12)


def test_status_and_plot_commands(reference_run, tmp_path):
    import json
    r = subprocess.run([MESHMARK, "study", "status", str(reference_run), "--spec", str(SMOKE), "--json"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["planned"] == 240 and d["remaining"] == 0 and d["rows"] == 240 and sum(d["by_status"].values()) == 240
    r = subprocess.run([MESHMARK, "study", "plot", str(reference_run), "--out", str(tmp_path / "plots")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    names = sorted(pathlib.Path(p).name for p in r.stdout.split())
    assert names == ["capacity_vs_size.png", "cdr_vs_strength.png", "correlation_vs_strength.png",
                     "detection_vs_deformation.png", "summary.csv"]
    import csv
    rows = list(csv.DictReader(open(tmp_path / "plots" / "summary.csv")))
    lap_none = next(x for x in rows if x["method"] == "laplacian" and x["attack"] == "none")
    assert lap_none["tasks"] == "6" and float(lap_none["cdr"]) == 1.0  # 3 meshes x 2 seeds; ok rows read back
