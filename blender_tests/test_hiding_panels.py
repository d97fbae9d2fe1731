"""The Steganography, Analysis, Steganalysis and Study sub-panels (issue 16) at the default sidebar
width: every state (folds open, Custom settings, file sources, each result, an error, a running
study) drawn with the recording layout and measured with ``blf.dimensions``; every choice is a menu;
tooltips speak to artists; results belong to their object."""
import bpy
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result
from blender_tests.test_addon_ui import _draw, _no_truncation, _texts

NEW = ("Steganography", "Analysis", "Steganalysis", "Study")


def _labels(d, panel):
    return [i.text for i in d[panel]]


@pytest.fixture
def fandisk(addon):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return rigs.mesh_object("Fandisk", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/fandisk.obj")))


def test_every_state_fits_the_default_width(fandisk, tmp_path, monkeypatch):
    s = bpy.context.scene.meshmark
    d = _draw(bpy.context)
    assert {"Text", "File", "Key", "Hide", "Reveal", "Advanced"} <= set(_labels(d, "Steganography"))
    assert {"Show", "Analyze", "Advanced"} <= set(_labels(d, "Analysis"))
    assert {"Detector", "Check"} <= set(_labels(d, "Steganalysis"))
    assert {"Study file", "Save the results to:", "Save the table and plot to:", "Run study",
            "Check frames"} <= set(_labels(d, "Study"))
    _no_truncation(d)
    # the folds: Auto by default (what it chooses, in words), Custom shows the settings
    s.stego_show_advanced = s.analysis_show_advanced = True
    d = _draw(bpy.context)
    assert {"Auto", "Custom", "Shading change 1 deg", "Spread: Even", "Save to"} <= set(_labels(d, "Steganography"))
    assert "Shading change 0.1 deg" in _labels(d, "Analysis")
    _no_truncation(d)
    s.stego_mode = s.analysis_mode = "CUSTOM"
    s.stego_source, s.model_source = "FILE", "FILE"
    d = _draw(bpy.context)
    assert {"Spread", "Even"} <= set(_labels(d, "Steganography")) and "File" in _labels(d, "Steganalysis")
    _no_truncation(d)
    s.stego_mode = s.analysis_mode = "AUTO"
    s.stego_source, s.model_source = "TEXT", "DEFAULT"
    # every result
    bpy.ops.meshmark.stego_embed(message="hello", key="k")
    d = _draw(bpy.context)
    assert "Hidden: 5 bytes" in _labels(d, "Steganography")
    _no_truncation(d)
    bpy.ops.meshmark.stego_extract(key="k")
    d = _draw(bpy.context)
    assert {"Found 5 bytes", "Text: hello"} <= set(_labels(d, "Steganography"))
    _no_truncation(d)
    bpy.ops.meshmark.stego_extract(key="wrong")
    assert {"Nothing found", "Check key and settings"} <= set(_labels(_draw(bpy.context), "Steganography"))
    with pytest.raises(RuntimeError):
        bpy.ops.meshmark.stego_embed(message="x" * 100000, key="k")
    d = _draw(bpy.context)
    box = [t for t in _labels(d, "Steganography")]
    assert any(t.startswith("too much to hide") for t in box)
    _no_truncation(d)
    bpy.ops.meshmark.analyze()
    d = _draw(bpy.context)
    r = last_result()
    assert f"Bits needed: {r['level_min']} to {r['level_max']}" in _labels(d, "Analysis")
    _no_truncation(d)
    bpy.ops.meshmark.steganalysis_detect()
    d = _draw(bpy.context)
    r = last_result()
    # three states in words, never a green check: the built-in detector is weak evidence
    assert r["state"] in ("marked", "clean") and r["marked"] == (r["probability"] > r["threshold"])
    verdict = "Something is probably hidden" if r["marked"] else "No sign of hidden data"
    assert verdict in _labels(d, "Steganalysis") and "CHECKMARK" not in [i.detail for i in d["Steganalysis"]]
    assert not any("%" in t or "needs" in t for t in _labels(d, "Steganalysis"))  # no raw score, no rates
    _no_truncation(d)
    bpy.ops.mesh.primitive_cube_add()  # 8 vertices: the detector cannot judge it
    bpy.ops.meshmark.steganalysis_detect()
    assert (last_result()["state"], last_result()["why"]) == ("cannot_judge", "too_small")
    d = _draw(bpy.context)
    assert {"Cannot judge this mesh", "Too small: 8 vertices"} <= set(_labels(d, "Steganalysis"))
    _no_truncation(d)
    rigs.select_only(fandisk)
    # a running study: the progress bar and how to stop it, in place of the button
    from meshmark_blender import session
    from meshmark_blender.operators.base import Job
    job = Job("Study")
    job.fraction, job.text = 0.4, "Study: 480 of 1200 tasks"
    monkeypatch.setitem(session.JOB, "running", job)
    assert s.study_progress == 40.0
    d = _draw(bpy.context)
    assert "Esc stops the study" in _labels(d, "Study") and "Run study" not in _labels(d, "Study")
    _no_truncation(d)


def test_results_belong_to_their_object(fandisk):
    bpy.ops.meshmark.analyze()
    assert any(t.startswith("Bits needed") for t in _texts(_draw(bpy.context)))
    bpy.ops.mesh.primitive_cube_add()
    assert not any(t.startswith("Bits needed") for t in _texts(_draw(bpy.context)))  # cleared for the cube
    rigs.select_only(bpy.data.objects["Fandisk"])
    assert any(t.startswith("Bits needed") for t in _texts(_draw(bpy.context)))


def test_choices_are_menus_and_tooltips_speak_to_artists(addon):
    s = bpy.context.scene.meshmark
    for name in ("stego_source", "stego_spread", "stego_mode", "analysis_mode", "analysis_show", "model_source"):
        assert s.bl_rna.properties[name].type == "ENUM", name
    rnas = [s.bl_rna] + [getattr(bpy.ops.meshmark, n).get_rna_type() for n in
                         ("stego_embed", "stego_extract", "analyze", "steganalysis_detect", "study")]
    for rna in rnas:
        assert "eq." not in rna.description and "thesis" not in rna.description.lower()
        for prop in rna.properties:
            text = prop.description.lower()
            assert "eq." not in text and "§" not in text and "thesis" not in text, prop.identifier
            assert "lsb" not in text and "quantiz" not in text, prop.identifier


def test_the_key_is_never_stored(fandisk, tmp_path):
    s = bpy.context.scene.meshmark
    s.key = "panel-secret-16"
    assert bpy.ops.meshmark.stego_embed(message="t") == {"FINISHED"}
    path = tmp_path / "k.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    assert b"panel-secret-16" not in path.read_bytes()
    for op in ("stego_embed", "stego_extract"):
        assert getattr(bpy.ops.meshmark, op).get_rna_type().properties["key"].is_skip_save
