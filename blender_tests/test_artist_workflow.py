"""The add-on as an artist uses it (issue 24): live modifiers, one keyfile per object, a character of
several objects as one carrier (embed, verify, issue, trace), hidden data that never reaches the
.blend, Hide refusing a watermarked mesh, undo only where the mesh changes, the pipeline API.

The bpy module has no window: modal jobs, undo itself, the autosave and the real panel are exercised
in Debian's Blender 3.4 under Xvfb (test_blender_ui.py, test_debian_blender.py)."""
import json
import os

import bpy
import numpy as np
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result


@pytest.fixture
def saved_scene(addon, tmp_path):
    """An empty scene saved as tmp_path/scene.blend (so '//' is tmp_path)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "scene.blend"))
    return tmp_path


def test_subdivision_and_armature_every_frame(saved_scene):
    """Suzanne with an unapplied Subdivision (level 2) and a neck and head rig: the mark goes into the
    cage, Verify and the frame check read the posed cage (the Subdivision left out, and said so) on
    every frame of a 48-frame sweep (the neck nods 8 degrees, the head nods 20 and turns 40 each way);
    the frames are the action's, the modifier is switched back on afterwards. Suzanne's cage is small
    (505 welded vertices): one letter takes the finest automatic setting, and a bend through the middle
    of the head loses it past 5 degrees (docs/blender.md)."""
    suz, sub, rig = rigs.suzanne_subdivided_and_rigged()
    ev = suz.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    n_eval = len(ev.vertices)
    suz.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh_clear()
    assert (len(suz.data.vertices), n_eval) == (507, 7958)  # the cage and what the viewport shows
    s = bpy.context.scene.meshmark
    s.key = "suzanne"
    assert bpy.ops.meshmark.embed(message="S") == {"FINISHED"}
    e = last_result()
    assert e["keyfile"] == str(saved_scene / "Suzanne.meshmark.json") and e["stored_cdr"] == 1.0
    assert any("Subdivision on 'Suzanne' is not applied" in w for w in e["warnings"])
    bpy.context.scene.frame_set(12)  # nodded and turned
    assert bpy.ops.meshmark.verify() == {"FINISHED"}
    v = last_result()
    assert v["detected"] and v["message"] == "S" and v["skipped_modifiers"] == ["Subdivision"]
    assert sub.show_viewport is True  # switched back on
    assert bpy.ops.meshmark.deformation_study(output_dir=str(saved_scene / "frames")) == {"FINISHED"}
    r = last_result()
    assert r["frames_from"] == "the action 'RigAction'" and [x["frame"] for x in r["rows"]] == list(range(1, 49))
    s_ = r["summary"]
    assert s_["max_disp_rel"] > 0.05  # it did bend
    assert (s_["frames"], s_["detected_frames"], s_["message_frames"]) == (48, 48, 48), s_
    assert sub.show_viewport is True and bpy.context.scene.frame_current == 12


def _arm(name, seed):
    obj = rigs.mesh_object(name, mesh=rigs.jittered_arm(seed))
    return obj


def test_two_objects_two_keyfiles_and_a_guarded_overwrite(saved_scene):
    a, b = _arm("HeroA", 0), _arm("HeroB", 1)
    s = bpy.context.scene.meshmark
    s.key = "studio"
    rigs.select_only(a)
    assert s.keyfile == "//HeroA.meshmark.json"  # the default: one keyfile per object, beside the .blend
    assert bpy.ops.meshmark.embed(message="A") == {"FINISHED"}
    rigs.select_only(b)
    assert s.keyfile == "//HeroB.meshmark.json"
    assert bpy.ops.meshmark.embed(message="B") == {"FINISHED"}
    assert sorted(p.name for p in saved_scene.glob("*.meshmark.json")) == ["HeroA.meshmark.json", "HeroB.meshmark.json"]
    for obj, msg in ((a, "A"), (b, "B")):
        rigs.select_only(obj)
        assert bpy.ops.meshmark.verify() == {"FINISHED"}
        assert (last_result()["detected"], last_result()["message"], last_result()["objects"]) == (True, msg, [obj.name])
    # marking A again into its keyfile: refused, naming the file and the mark it holds
    rigs.select_only(a)
    before = (saved_scene / "HeroA.meshmark.json").read_text()
    with pytest.raises(RuntimeError, match=r"'HeroA.meshmark.json' already exists: .* holds the mark in HeroA "
                                           r"\(message 'A'\)\. Without it that mark can no longer be read"):
        bpy.ops.meshmark.embed(message="A2")
    assert (saved_scene / "HeroA.meshmark.json").read_text() == before
    # Hide refuses the watermarked mesh (it would erase the mark) and says how to go on
    co = rigs.base_coords(a).copy()
    with pytest.raises(RuntimeError, match="'HeroA' carries a watermark .*would erase it"):
        bpy.ops.meshmark.stego_embed(message="hidden", key="k")
    assert np.array_equal(rigs.base_coords(a), co)
    assert bpy.ops.meshmark.stego_embed(message="hidden", key="k", replace_watermark=True) == {"FINISHED"}
    assert any("watermark of 'HeroA' is gone" in w for w in last_result()["warnings"])
    assert bpy.ops.meshmark.verify() == {"FINISHED"} and last_result()["detected"] is False


def test_hidden_and_revealed_text_never_reach_the_blend(saved_scene):
    bpy.ops.mesh.primitive_monkey_add()
    bpy.ops.object.modifier_add(type="SUBSURF")
    bpy.context.object.modifiers[0].levels = 2
    bpy.ops.object.modifier_apply(modifier=bpy.context.object.modifiers[0].name)
    s = bpy.context.scene.meshmark
    text, key = "Rendezvous-at-pier-9 Qx7", "hush-k3y-5551"
    s.key, s.stego_source, s.stego_text = key, "TEXT", text
    s.message = "visible-M"  # the watermark message is a scene setting: saved, and found by the search
    assert bpy.ops.meshmark.stego_embed() == {"FINISHED"}
    assert bpy.ops.meshmark.stego_extract() == {"FINISHED"}
    assert last_result()["text"] == text and s.stego_text == text  # shown in this session
    path = saved_scene / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path), compress=False)
    data = path.read_bytes()
    assert data[:7] == b"BLENDER" and b"visible-M" in data  # uncompressed: the search sees saved strings
    found = [name for name, needle in rigs.secret_needles(text, key).items() if needle in data]
    assert found == [], found
    bpy.ops.wm.open_mainfile(filepath=str(path))
    assert bpy.data.objects["Suzanne"].get("meshmark_last_result") is None


def test_undo_only_where_the_mesh_changes():
    changing = {"embed", "stego_embed", "analyze", "select_parts"}
    for name in ("embed", "verify", "capacity", "select_parts", "save_keyfile", "load_keyfile", "issue_copies",
                 "trace", "stego_embed", "stego_extract", "analyze", "steganalysis_detect", "deformation_study",
                 "study"):
        flags = getattr(bpy.types, f"MESHMARK_OT_{name}").bl_options
        assert ("UNDO" in flags) == (name in changing), (name, flags)
    # the text to hide never sits in Blender's operator history (its redo panel)
    assert "REGISTER" not in bpy.types.MESHMARK_OT_stego_embed.bl_options
    assert "REGISTER" not in bpy.types.MESHMARK_OT_stego_extract.bl_options


def _two_part_character():
    """A jittered tube (6,402 vertices) cut in two objects (upper, lower) skinned to one two-bone armature."""
    from meshmark.shapes import cylinder
    m = cylinder(segments=32, rings=200)
    m = m.with_vertices(m.V + np.random.default_rng(3).uniform(-0.25, 0.25, m.V.shape) * 2 * np.pi * 0.15 / 32)
    z = m.V[:, 2]
    F = m.F
    upper = (z[F] > 1.0).all(1)
    parts = []
    for name, sel in (("Char_Lower", ~upper), ("Char_Upper", upper)):
        used = np.unique(F[sel])
        remap = np.full(m.n_vertices, -1)
        remap[used] = np.arange(used.size)
        parts.append(rigs.mesh_object(name, V=m.V[used], F=remap[F[sel]]))
    rig = rigs.chain_armature("CharRig", [(0, 0, 0), (0, 0, 1), (0, 0, 2)])
    for p in parts:
        rigs.rig_auto(p, rig)
    return parts, rig


def test_character_parts_issue_trace_and_the_api(saved_scene, monkeypatch):
    from meshmark_blender import api
    parts, rig = _two_part_character()
    lower, upper = parts
    # the panel's hint: one part of two selected
    rigs.select_only(lower)
    from meshmark_blender import targets
    assert targets.left_out(bpy.context, targets.from_selection(bpy.context)) == ["Char_Upper"]
    assert bpy.ops.meshmark.select_parts() == {"FINISHED"}
    assert sorted(o.name for o in bpy.context.selected_objects if o.type == "MESH") == ["Char_Lower", "Char_Upper"]
    # the API: one mark over both parts, the keyfile named after them, read from either
    r = api.embed(parts, message="C", key="char")
    assert r.ok and r.keyfile == str(saved_scene / "Char.meshmark.json") and r.objects == ["Char_Lower", "Char_Upper"]
    assert [p["object"] for p in json.loads(open(r.keyfile).read())["mesh"]["parts"]] == ["Char_Lower", "Char_Upper"]
    rigs.bend_over_frames(rig, "b1", (1, 10), (0, 45))
    bpy.context.scene.frame_set(10)
    v = api.verify([upper])
    assert (v.detected, v.message, v.objects) == (True, "C", ["Char_Lower", "Char_Upper"])
    # issue copies of the character (key not stored: Trace takes the panel's key), into '~/copies'
    monkeypatch.setenv("HOME", str(saved_scene))
    bpy.context.scene.meshmark.key = "owner"
    rigs.select_only(lower)
    upper.select_set(True)
    assert bpy.ops.meshmark.issue_copies(copies=3, key="owner", registry="//copies.sqlite", output_dir="~/copies",
                                         store_key=False) == {"FINISHED"}
    made = last_result()["copies"]
    assert [c["id"] for c in made] == ["0001", "0002", "0003"]
    assert all(os.path.dirname(c["path"]) == str(saved_scene / "copies") for c in made)
    assert b"owner" not in (saved_scene / "copies.sqlite").read_bytes()
    # copy 0002 leaks: its positions put into the two parts, posed, traced
    leaked = meshmark.read_mesh(made[1]["path"]).V
    n = len(lower.data.vertices)
    for obj, V in ((lower, leaked[:n]), (upper, leaked[n:])):
        obj.data.vertices.foreach_set("co", V.astype(np.float32).ravel())
        obj.data.update()
    t = api.trace(parts, registry="//copies.sqlite")
    assert t.copy == "0002" and t.detected and t.objects == ["Char_Lower", "Char_Upper"]
    # a missing part is named (the other is still read)
    bpy.data.objects.remove(upper, do_unlink=True)
    bpy.context.view_layer.update()
    rigs.select_only(lower)
    try:
        bpy.ops.meshmark.verify(keyfile="//Char.meshmark.json")
        said = " ".join(last_result()["warnings"])
    except RuntimeError as exc:
        said = str(exc)
    assert "Char_Upper" in said and ("not in the scene" in said or "missing" in said), said
