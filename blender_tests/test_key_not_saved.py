"""The panel's key is never written into the .blend (issue 11): after Embed and Save, a byte search
of the saved file finds no key, while the message typed beside it is found (so the search works:
the file is not compressed). Verify still works in the session, and with a key-less keyfile."""
import json

import bpy


def _blend_bytes(path):
    with open(path, "rb") as f:
        data = f.read()
    assert data[:7] == b"BLENDER"  # uncompressed: a byte search sees every string
    return data


def test_key_not_in_saved_blend(empty_scene, addon, tmp_path):
    bpy.ops.mesh.primitive_monkey_add()
    bpy.ops.object.modifier_add(type="SUBSURF")
    bpy.context.object.modifiers[0].levels = 2
    bpy.ops.object.modifier_apply(modifier=bpy.context.object.modifiers[0].name)
    s = bpy.context.scene.meshmark
    key = "Sekr1t-k3y-7f3a9c"
    s.key = key
    s.message = "M4e1"
    s.method = "cho-mean"
    kf = tmp_path / "k.json"
    assert bpy.ops.meshmark.embed(keyfile=str(kf)) == {"FINISHED"}
    assert s.key == key  # still there for this session
    assert json.loads(kf.read_text())["key"] == key  # the keyfile holds it (Store key on)
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), compress=False)
    data = _blend_bytes(blend)
    assert b"M4e1" in data and str(kf).encode() in data  # saved scene strings are found ...
    for enc in (key.encode("utf-8"), key.encode("utf-16-le")):
        assert enc not in data  # ... the key is not
    assert bpy.ops.meshmark.verify() == {"FINISHED"}
    assert json.loads(s.last_result)["detected"] is True
    # reopened: the key field is empty, and nothing of it came back from the file
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    assert bpy.context.scene.meshmark.key in ("", key)  # in-session memory may keep it; the file did not


def test_keyless_keyfile_uses_panel_key(empty_scene, addon, tmp_path):
    bpy.ops.mesh.primitive_monkey_add()
    bpy.ops.object.modifier_add(type="SUBSURF")
    bpy.context.object.modifiers[0].levels = 2
    bpy.ops.object.modifier_apply(modifier=bpy.context.object.modifiers[0].name)
    s = bpy.context.scene.meshmark
    s.key, s.method, s.store_key, s.message = "panel-key-55", "cho-mean", False, "h"
    kf = tmp_path / "k.json"
    assert bpy.ops.meshmark.embed(keyfile=str(kf)) == {"FINISHED"}
    assert b"panel-key-55" not in kf.read_bytes()
    assert bpy.ops.meshmark.verify(keyfile=str(kf)) == {"FINISHED"}
    assert json.loads(s.last_result)["detected"] is True
    s.key = ""
    try:
        bpy.ops.meshmark.verify(keyfile=str(kf))
    except RuntimeError as exc:
        assert "holds no key" in str(exc)
    else:
        assert "holds no key" in s.last_result
