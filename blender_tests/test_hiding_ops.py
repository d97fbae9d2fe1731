"""The steganography, analysis, steganalysis and background-study operators (issue 16): bad input is an
error report with the mesh bit-identical (coordinates and attributes); success cases compare with the
Python API on the same mesh (the stego message through Blender's float32 storage and a saved .blend,
the heat map's attribute against meshmark.analysis, the detector's probabilities against
meshmark.steganalysis)."""
import json
import os

import bpy
import numpy as np
import pytest

import meshmark
from meshmark import analysis, stego
from meshmark.steganalysis.model import Model
from blender_tests import rigs
from blender_tests.rigs import last_result

OPS = ("stego_embed", "stego_extract", "analyze", "steganalysis_detect")
ARGS = {"stego_embed": dict(message="hello", key="k"), "stego_extract": dict(key="k"), "analyze": {},
        "steganalysis_detect": {}}


def _state(obj):
    """Everything an operator could change on the mesh: every coordinate array and the attributes."""
    me = obj.data
    from meshmark_blender import bridge
    return [c.tobytes() for c in bridge.snapshot_coords(me)], sorted(a.name for a in me.attributes)


def _fails(name, match, **kw):
    with pytest.raises(RuntimeError, match=match):
        getattr(bpy.ops.meshmark, name)(**kw)
    r = last_result()
    assert r["ok"] is False and r["error"] and r["operator"] == f"meshmark.{name}"
    return r["error"]


@pytest.fixture
def fandisk(addon):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return rigs.mesh_object("Fandisk", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/fandisk.obj")))


def test_no_object_and_not_a_mesh(fandisk):
    s0 = _state(fandisk)
    fandisk.select_set(False)
    bpy.context.view_layer.objects.active = None
    for name in OPS:
        assert _fails(name, "no active object", **ARGS[name])
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    bpy.context.scene.collection.objects.link(cam)
    rigs.select_only(cam)
    for name in OPS:
        assert "is a camera, not a mesh" in _fails(name, "not a mesh", **ARGS[name])
    assert _state(fandisk) == s0


def test_mesh_too_small(addon):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    tri = rigs.mesh_object("Tri", V=np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.]]), F=np.array([[0, 1, 2]]))
    s0 = _state(tri)
    for name in OPS:
        if name == "steganalysis_detect":  # a verdict, not an error: the detector cannot judge it
            assert bpy.ops.meshmark.steganalysis_detect() == {"FINISHED"}
            r = last_result()
            assert r["state"] == "cannot_judge" and r["why"] == "too_small" and "3 vertices" in json.dumps(r), r
            continue
        assert "too small" in _fails(name, "too small", **ARGS[name])
    assert _state(tri) == s0


def test_stego_message_too_long_and_empty(fandisk, tmp_path):
    s0 = _state(fandisk)
    room = stego.capacity(meshmark.Mesh.from_polygons(rigs.base_coords(fandisk).astype(np.float64),
                                                      *rigs.bridge_faces(fandisk)), tolerance=1.0,
                          precision="float32")["max_message_bytes"]
    err = _fails("stego_embed", "too much to hide", message="x" * (room + 1), key="k")
    assert f"{room + 1} bytes, at most {room} bytes fit" in err
    _fails("stego_embed", "text is empty", message="", key="k")
    _fails("stego_embed", "key is empty", message="x", key="")
    _fails("stego_embed", "does not exist", message_file=str(tmp_path / "nope.bin"), key="k")
    _fails("stego_extract", "key is empty", key="")
    assert _state(fandisk) == s0


def test_stego_refuses_when_the_stored_mesh_would_not_decode(fandisk, monkeypatch):
    """The read-back check: if the mesh as Blender stores it does not give the message back, every
    coordinate is put back (simulated with an extract that finds nothing)."""
    s0 = _state(fandisk)
    from meshmark_blender.tasks import hiding
    monkeypatch.setattr(hiding.stego, "extract", lambda *a, **k: stego.ExtractResult(False, None, "damaged message"))
    assert "would not read back" in _fails("stego_embed", "would not read back", message="hello", key="k")
    assert _state(fandisk) == s0


def test_stego_round_trip_through_float32_and_a_blend(fandisk, tmp_path):
    s0 = _state(fandisk)
    assert bpy.ops.meshmark.stego_embed(message="Grüße aus Blender", key="secret") == {"FINISHED"}
    r = last_result()
    assert r["ok"] and r["read_back"] and r["bytes"] == len("Grüße aus Blender".encode()) and r["precision"] == "float32"
    V = rigs.base_coords(fandisk)
    assert _state(fandisk)[0] != s0[0]  # it did move vertices
    path = str(tmp_path / "m.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    assert b"secret" not in open(path, "rb").read()  # the key is not in the .blend
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Fandisk"]
    assert np.array_equal(rigs.base_coords(obj), V)
    # the Python API on the stored float32 mesh reads the same message
    m = meshmark.Mesh.from_polygons(V.astype(np.float64), *rigs.bridge_faces(obj))
    assert stego.extract(m, "secret", precision="float32").message == "Grüße aus Blender".encode()
    rigs.select_only(obj)
    assert bpy.ops.meshmark.stego_extract(key="secret") == {"FINISHED"}
    r = last_result()
    assert r["found"] and r["text"] == "Grüße aus Blender"
    assert bpy.ops.meshmark.stego_extract(key="wrong") == {"FINISHED"}  # an answer (warning), not an error
    assert last_result()["found"] is False


def test_stego_file_payload_and_panel_settings(fandisk, tmp_path):
    src = tmp_path / "secret.bin"
    src.write_bytes(bytes(range(256)) * 3)
    s = bpy.context.scene.meshmark
    s.key, s.stego_mode, s.stego_tolerance, s.stego_spread = "k2", "CUSTOM", 2.0, "curvature"
    s.stego_source, s.stego_file = "FILE", str(src)
    assert bpy.ops.meshmark.stego_embed() == {"FINISHED"}
    r = last_result()
    assert (r["bytes"], r["file"], r["tolerance_deg"], r["adaptive"]) == (768, "secret.bin", 2.0, "curvature")
    out = tmp_path / "out.bin"
    assert bpy.ops.meshmark.stego_extract(out_file=str(out)) == {"FINISHED"}
    assert out.read_bytes() == src.read_bytes() and last_result()["text"] is None
    s.stego_mode = "AUTO"  # Auto: 1 deg, even: another setting, nothing found
    assert bpy.ops.meshmark.stego_extract() == {"FINISHED"} and last_result()["found"] is False


def test_analyze_attribute_equals_the_analysis_levels(fandisk):
    from meshmark_blender import bridge, heatmap as hiding_ops
    s0 = _state(fandisk)
    assert bpy.ops.meshmark.analyze() == {"FINISHED"}
    r = last_result()
    me = fandisk.data
    mesh = bridge.base_mesh(fandisk)
    want = analysis.adaptive_levels(mesh, 0.1)
    got = np.empty(len(me.vertices), np.int32)
    me.attributes[hiding_ops.LEVEL_ATTR].data.foreach_get("value", got)
    assert np.array_equal(got, want)
    assert (r["level_min"], r["level_max"]) == (int(want.min()), int(want.max())) and r["level_max"] > r["level_min"]
    assert sum(r["histogram"].values()) == mesh.n_vertices
    # the curvature change: |kappa' - kappa| after the dithered rounding at those levels
    q = analysis.quantize(mesh, levels=want, seed=0)
    dk = np.abs(analysis.gaussian_curvature(q)["kappa"] - analysis.gaussian_curvature(mesh)["kappa"])
    got_dk = np.empty(len(me.vertices), np.float32)
    me.attributes[hiding_ops.CURV_ATTR].data.foreach_get("value", got_dk)
    assert np.allclose(got_dk, dk.astype(np.float32)) and dk.max() > 0
    # the colours: blue for the fewest bits, red for the most
    col = np.empty(4 * len(me.vertices), np.float32)
    me.color_attributes[hiding_ops.LEVEL_COLOR].data.foreach_get("color", col)
    col = col.reshape(-1, 4)
    assert np.allclose(col[want == want.min()][:, :3], [0, 0, 1]) and np.allclose(col[want == want.max()][:, :3], [1, 0, 0])
    assert me.color_attributes.active_color.name == hiding_ops.LEVEL_COLOR
    bpy.context.scene.meshmark.analysis_show = "CURVATURE"  # the Show menu switches the heat map
    assert me.color_attributes.active_color.name == hiding_ops.CURV_COLOR
    assert _state(fandisk)[0] == s0[0]  # coordinates untouched
    assert bpy.ops.meshmark.analyze(tolerance=1.0, mode="GLOBAL") == {"FINISHED"}
    lv = analysis.quantization_level(mesh, 1.0)
    assert (last_result()["level_min"], last_result()["level_max"]) == (lv, lv)


def test_detect_equals_the_python_api_and_bad_models(fandisk, tmp_path):
    from meshmark_blender import bridge
    s0 = _state(fandisk)
    assert bpy.ops.meshmark.steganalysis_detect() in ({"FINISHED"},)
    r = last_result()
    want = Model.load().detect(bridge.base_mesh(fandisk))
    assert r["probability"] == want["probability"] and r["methods"] == want["methods"] and r["model"] == "built-in"
    # a chosen model file: the shipped one copied
    import shutil
    from meshmark.steganalysis.model import DEFAULT_MODEL
    mine = tmp_path / "mine.npz"
    shutil.copy(DEFAULT_MODEL, mine)
    s = bpy.context.scene.meshmark
    s.model_source, s.model_file = "FILE", str(mine)
    assert bpy.ops.meshmark.steganalysis_detect() == {"FINISHED"}
    assert last_result()["model"] == str(mine) and last_result()["probability"] == want["probability"]
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a model at all")
    assert "not a meshmark steganalysis model" in _fails("steganalysis_detect", "not a meshmark", model=str(bad))
    _fails("steganalysis_detect", "does not exist", model=str(tmp_path / "none.npz"))
    s.model_file = ""
    _fails("steganalysis_detect", "choose the detector file")
    assert _state(fandisk) == s0




def test_study_runs_a_spec_and_reports_bad_specs(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    spec = tmp_path / "s.toml"
    spec.write_text(rigs.study_spec(rigs.shared_mesh("classic/fandisk.obj"), attacks=['name = "noise"\ngrid = { strength = [0.001] }']))
    out = tmp_path / "out"
    assert bpy.ops.meshmark.study(spec=str(spec), out=str(out)) == {"FINISHED"}
    r = last_result()
    assert r["ok"] and r["planned"] == 2 and r["done"] == 2 and r["summary"]["ok"] == 2
    from meshmark.study import engine
    assert len(engine.finished_keys(out)) == 2 and os.path.isdir(r["results"])
    assert bpy.ops.meshmark.study(spec=str(spec), out=str(out)) == {"FINISHED"}  # resumed: nothing to do
    assert last_result()["summary"]["skipped"] == 2
    bad = tmp_path / "bad.toml"
    bad.write_text(spec.read_text().replace('name = "cho-mean"', 'name = "no-such-method"'))
    assert "no-such-method" in _fails("study", "no-such-method", spec=str(bad), out=str(tmp_path / "o2"))
    _fails("study", "does not exist", spec=str(tmp_path / "none.toml"), out=str(out))
    bpy.context.scene.meshmark.study_spec = ""
    _fails("study", "choose the study file")
