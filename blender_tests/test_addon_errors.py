"""(5) Bad input: every failure is an error report (bpy.ops raises RuntimeError for an ERROR report
when called from Python), {'CANCELLED'}, an error in last_result, and bit-identical coordinates."""
import json

import bmesh
import bpy
import numpy as np
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result


def _coords(obj):
    return rigs.base_coords(obj).copy()


def _fails(op, match, **kw):
    with pytest.raises(RuntimeError, match=match):
        op(**kw)
    r = last_result()
    assert r["ok"] is False and r["error"]
    return r["error"]


@pytest.fixture
def elephant(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    return obj


def test_active_object_not_a_mesh(elephant, tmp_path):
    V0 = _coords(elephant)
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    bpy.context.scene.collection.objects.link(cam)
    rigs.select_only(cam)
    _fails(bpy.ops.meshmark.embed, "is a camera, not a mesh", message="x", key="k", keyfile=str(tmp_path / "k.json"))
    _fails(bpy.ops.meshmark.verify, "not a mesh", keyfile=str(tmp_path / "k.json"))
    _fails(bpy.ops.meshmark.capacity, "not a mesh")
    assert np.array_equal(_coords(elephant), V0)
    assert not (tmp_path / "k.json").exists()


def test_existing_keyfile_is_not_overwritten_without_consent(elephant, tmp_path):
    """issue 10 item 5: automatic parameters take "ACME 2024"; a second Embed into the same keyfile
    fails (the dialog's confirmation sets overwrite) and changes nothing."""
    kf = tmp_path / f"{elephant.name}.meshmark.json"
    assert bpy.ops.meshmark.embed(message="ACME 2024", key="k", keyfile=str(kf)) == {"FINISHED"}
    first = kf.read_text()
    V1 = _coords(elephant)
    _fails(bpy.ops.meshmark.embed, "already exists", message="other", key="k2", keyfile=str(kf))
    assert kf.read_text() == first and np.array_equal(_coords(elephant), V1)
    assert bpy.ops.meshmark.embed(message="other", key="k2", keyfile=str(kf), overwrite=True) == {"FINISHED"}
    assert kf.read_text() != first


def test_no_object_selected(elephant, tmp_path):
    V0 = _coords(elephant)
    elephant.select_set(False)
    bpy.context.view_layer.objects.active = None
    _fails(bpy.ops.meshmark.embed, "no active object", message="x", key="k", keyfile=str(tmp_path / "k.json"))
    _fails(bpy.ops.meshmark.deformation_study, "no active object", keyfile=str(tmp_path / "k.json"),
           output_dir=str(tmp_path))
    assert np.array_equal(_coords(elephant), V0)


def test_mesh_too_small(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    V0 = _coords(cube)
    # in the user's words, with the parameters named as the panel names them
    _fails(bpy.ops.meshmark.embed, "^Error: meshmark: mesh too small to carry a mark", message="x", key="k",
           keyfile=str(tmp_path / "k.json"))
    err = _fails(bpy.ops.meshmark.embed, "mesh too small to carry a mark", message="x", key="k", K=4, n_thr=1,
                 keyfile=str(tmp_path / "k.json"))  # the cube's Laplacian lengths are all equal
    assert "Laplacian" not in err and "range" not in err
    err = _fails(bpy.ops.meshmark.embed, "mesh too small to carry a mark: 8 vertices for 64 Bins", method="cho-mean",
                 message="x", key="k", keyfile=str(tmp_path / "k.json"))
    bpy.ops.mesh.primitive_uv_sphere_add()
    sphere = bpy.context.active_object
    S0 = _coords(sphere)
    err = _fails(bpy.ops.meshmark.embed, "mesh too small to carry a mark: it offers only", message="x", key="k",
                 keyfile=str(tmp_path / "k.json"))
    # Settings: Auto walks the ladder and reports its largest rung: 1 carrier at Bins 61, Min. pair size 5
    assert "offers only 1 of the 8 bits" in err and "(Bins 61, Min. pair size 5)" in err and "n_thr" not in err and "K=" not in err
    _fails(bpy.ops.meshmark.embed, "Min. pair size must be", message="x", key="k", K=20, n_thr=0,
           keyfile=str(tmp_path / "k.json"))
    assert np.array_equal(_coords(cube), V0) and np.array_equal(_coords(sphere), S0)
    assert not (tmp_path / "k.json").exists()


def test_message_longer_than_capacity(elephant, tmp_path):
    V0 = _coords(elephant)
    # the thesis parameters (Settings: Custom, or params="thesis"): 44 carriers; 72 data + 20 check
    # bits need 138 (docs/coding.md)
    err = _fails(bpy.ops.meshmark.embed, "the mesh can carry 44 bits", message="ACME 2024", key="k",
                 keyfile=str(tmp_path / "k.json"), params="thesis")
    assert "needs 138 bits" in err and "(Bins 286, Min. pair size 46)" in err and "at most 1 bytes of text fit" in err
    assert err.startswith("message too long for this mesh")
    _fails(bpy.ops.meshmark.embed, "at most 31 bytes", message="x" * 40, key="k", keyfile=str(tmp_path / "k.json"))
    _fails(bpy.ops.meshmark.embed, "message is empty", message="", key="k", keyfile=str(tmp_path / "k.json"))
    _fails(bpy.ops.meshmark.embed, "key is empty", message="E", key="", keyfile=str(tmp_path / "k.json"))
    _fails(bpy.ops.meshmark.embed, "folder does not exist", message="E", key="k",
           keyfile=str(tmp_path / "missing" / "k.json"))
    assert np.array_equal(_coords(elephant), V0)
    assert not (tmp_path / "k.json").exists()


def test_edit_mode_is_refused(elephant, tmp_path):
    V0 = _coords(elephant)
    bpy.ops.object.mode_set(mode="EDIT")
    _fails(bpy.ops.meshmark.embed, "Edit Mode", message="E", key="k", keyfile=str(tmp_path / "k.json"))
    bpy.ops.object.mode_set(mode="OBJECT")
    assert np.array_equal(_coords(elephant), V0)


def test_keyfile_wrong_or_corrupt(elephant, tmp_path):
    kf = tmp_path / "k.json"
    assert bpy.ops.meshmark.embed(message="E", key="k", keyfile=str(kf)) == {"FINISHED"}
    V1 = _coords(elephant)
    _fails(bpy.ops.meshmark.verify, "there is no keyfile", keyfile=str(tmp_path / "none.json"))
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "meshmark-keyfile", "version": 1, "meth')
    _fails(bpy.ops.meshmark.verify, "not valid JSON", keyfile=str(bad))
    d = json.loads(kf.read_text())
    d["payload"]["bits"] = d["payload"]["bits"][::-1] + "1"
    bad.write_text(json.dumps(d))
    _fails(bpy.ops.meshmark.verify, "does not match", keyfile=str(bad))
    bad.write_text(json.dumps({"hello": 1}))
    _fails(bpy.ops.meshmark.deformation_study, "not a meshmark keyfile", keyfile=str(bad), output_dir=str(tmp_path))
    _fails(bpy.ops.meshmark.load_keyfile, "not a meshmark keyfile", filepath=str(bad))
    # a valid keyfile with the wrong key: no false "found"
    assert bpy.ops.meshmark.verify(keyfile=str(kf), key="not-k") == {"FINISHED"}
    assert last_result()["detected"] is False and last_result()["message"] is None
    assert np.array_equal(_coords(elephant), V1)


def test_verify_on_a_different_mesh(elephant, tmp_path):
    """A mesh of another (welded) vertex count whose mark is not found is an error; the core still
    extracts blindly (a cropped copy may keep the mark), and a mark found despite the count is a
    detection with a warning."""
    kf = tmp_path / "k.json"
    assert bpy.ops.meshmark.embed(message="E", key="k", keyfile=str(kf)) == {"FINISHED"}
    E1 = _coords(elephant)
    arm = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
    A0 = _coords(arm)
    err = _fails(bpy.ops.meshmark.verify, "has 20482 vertices but the keyfile was made for a mesh of 20007",
                 keyfile=str(kf))
    assert "Verify is run on a different mesh" in err
    r = last_result()  # the figures are kept with the error
    assert (r["n_vertices"], r["expected_vertices"], r["detected"], r["message"]) == (20482, 20007, False, None)
    assert r["p_false_alarm"] > 1e-6 and r["cdr"] < 0.8
    _fails(bpy.ops.meshmark.verify, "different mesh", keyfile=str(kf), evaluated=False)
    # the marked elephant with its 20 topmost vertices deleted: another count, but the mark is there
    V = rigs.base_coords(elephant)
    cut = elephant.copy()
    cut.data = elephant.data.copy()
    bpy.context.scene.collection.objects.link(cut)
    bm = bmesh.new()
    bm.from_mesh(cut.data)
    bm.verts.ensure_lookup_table()
    bmesh.ops.delete(bm, geom=[bm.verts[i] for i in np.argsort(V[:, 2])[-20:]], context="VERTS")
    bm.to_mesh(cut.data)
    bm.free()
    rigs.select_only(cut)
    C0 = _coords(cut)
    assert bpy.ops.meshmark.verify(keyfile=str(kf)) == {"FINISHED"}
    r = last_result()
    assert (r["ok"], r["n_vertices"], r["detected"], r["cdr"], r["message"]) == (True, 19987, True, 1.0, "E")
    assert "19987 vertices but the keyfile was made for 20007" in r["warnings"][0]
    assert np.array_equal(_coords(arm), A0) and np.array_equal(_coords(elephant), E1)
    assert np.array_equal(_coords(cut), C0)


def test_embed_keeps_shape_key_offsets_uvs_groups_attributes(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    me = obj.data
    me.uv_layers.new(name="UV")
    uv0 = np.random.default_rng(1).random(2 * len(me.loops)).astype(np.float32)
    me.uv_layers[0].data.foreach_set("uv", uv0)
    g = obj.vertex_groups.new(name="half")
    g.add(list(range(0, len(me.vertices), 2)), 0.5, "REPLACE")
    attr = me.attributes.new("heat", "FLOAT", "POINT")
    attr.data.foreach_set("value", np.arange(len(me.vertices), dtype=np.float32))
    obj.modifiers.new("sub", "SUBSURF")
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="Fat")
    base0 = rigs.base_coords(obj).astype(np.float64)
    fat = np.empty(3 * len(me.vertices), np.float32)
    key.data.foreach_get("co", fat)
    fat = fat.reshape(-1, 3) + np.float32(0.01)
    key.data.foreach_set("co", fat.ravel())
    kf = str(tmp_path / "k.json")
    assert bpy.ops.meshmark.embed(message="E", key="k", keyfile=kf) == {"FINISHED"}
    basis = np.empty(3 * len(me.vertices), np.float32)
    me.shape_keys.key_blocks["Basis"].data.foreach_get("co", basis)
    fat1 = np.empty(3 * len(me.vertices), np.float32)
    key.data.foreach_get("co", fat1)
    D = basis.reshape(-1, 3) - base0
    assert np.abs(D).max() > 0  # the Basis moved ...
    np.testing.assert_allclose(fat1.reshape(-1, 3) - basis.reshape(-1, 3), fat - base0, atol=1e-6)  # offsets kept
    uv1 = np.empty_like(uv0)
    me.uv_layers[0].data.foreach_get("uv", uv1)
    assert np.array_equal(uv0, uv1)
    assert sum(1 for v in me.vertices if v.groups) == (len(me.vertices) + 1) // 2
    h = np.empty(len(me.vertices), np.float32)
    me.attributes["heat"].data.foreach_get("value", h)
    assert np.array_equal(h, np.arange(len(me.vertices), dtype=np.float32))
    assert bpy.ops.meshmark.verify(keyfile=kf, evaluated=False) == {"FINISHED"}
    assert last_result()["cdr"] == 1.0 and last_result()["message"] == "E"
    key.value = 1.0  # the Fat key (a uniform offset) does not hide the mark
    bpy.context.view_layer.update()
    obj.modifiers["sub"].show_viewport = False
    assert bpy.ops.meshmark.verify(keyfile=kf, evaluated=True) == {"FINISHED"}
    assert last_result()["cdr"] == 1.0
    # Undo cannot be exercised here: the bpy module has no window, so ed.undo never polls. It is tested
    # in Debian's Blender GUI under Xvfb (test_debian_blender.py, tools/blender_undo.py).
    assert not bpy.ops.ed.undo.poll()
    assert "UNDO" in bpy.types.MESHMARK_OT_embed.bl_options
