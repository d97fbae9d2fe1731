"""The examples of the new operators (examples/blender_stego_embed.py, blender_stego_extract.py,
blender_analyze.py, blender_steganalysis.py, blender_study.py) in background Blender (the bpy module),
each in its own process, chained as a user would."""
import json
import os

from blender_tests import rigs
from blender_tests.test_examples_blender import _run
from meshmark.steganalysis.model import Model


def test_stego_examples(tmp_path):
    blend = tmp_path / "hidden.blend"
    r, out = _run("blender_stego_embed.py", "--out", blend, "--message", "under the bridge")
    assert (r["operator"], r["bytes"], r["read_back"], r["precision"]) == ("meshmark.stego_embed", 16, True, "float32")
    assert b"example-key" not in blend.read_bytes()
    r, out = _run("blender_stego_extract.py", "--blend", blend)
    assert (r["found"], r["text"]) == (True, "under the bridge")
    r, _ = _run("blender_stego_extract.py", "--blend", blend, "--key", "other")
    assert r["found"] is False


def test_analyze_and_steganalysis_examples(tmp_path):
    import meshmark
    from meshmark import analysis
    path = rigs.shared_mesh("classic/fandisk.obj")
    r, _ = _run("blender_analyze.py", "--mesh", path, "--out", tmp_path / "heat.blend")
    m = meshmark.read_mesh(path)
    m32 = m.with_vertices(m.V.astype("float32").astype("float64"))  # what Blender stores
    lv = analysis.adaptive_levels(m32, 0.1)
    assert r["operator"] == "meshmark.analyze" and r["colors"] == ["Meshmark precision", "Meshmark curvature change"]
    assert (r["level_min"], r["level_max"]) == (int(lv.min()), int(lv.max()))
    assert sum(r["histogram"].values()) == m.n_vertices and r["histogram"] == {
        str(k): int(c) for k, c in enumerate(__import__("numpy").bincount(lv)) if c}
    assert (tmp_path / "heat.blend").is_file()
    r, _ = _run("blender_steganalysis.py", "--mesh", path)
    assert r["operator"] == "meshmark.steganalysis_detect" and r["model"] == "built-in"
    want = Model.load().detect(m32)
    assert abs(r["probability"] - want["probability"]) < 1e-12


def test_study_example(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(rigs.study_spec(rigs.shared_mesh("classic/fandisk.obj"), name="example"))
    r, out = _run("blender_study.py", "--spec", spec, "--out", tmp_path / "out")
    assert r["operator"] == "meshmark.study" and r["summary"]["ok"] == r["planned"] == 1
    assert os.path.isdir(r["results"]) and "1 ok" in out
