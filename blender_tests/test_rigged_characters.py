"""(3) The real rigged characters: import with Blender's glTF importer, select the character's parts
(several objects, not joined) and embed them as one carrier, play the animations and verify at every
frame with the frame-check operator (any one part selected: the keyfile's parts are read).

Both files are non-indexed or flat-shaded glTF: Blender imports every split vertex as a separate
copy (the Fox as 576 loose triangles). The core welds exactly coincident vertices before the method
runs (docs/mesh_model.md), so the Laplacian sees the real surface: the Fox is 290 vertices, the
Knight 2,145 (its 6 skinned parts) or 2,454 (as shown, with helmet and cape). All are far below
what the thesis' method is made for (§7.4: K = ceil(N/70) bins, at least 46 elements per pair): at
thesis defaults they offer 1, 6 and 8 carrier bits, less than one framed text byte.

Measured against the targets (detected at every frame, mean CDR >= 0.9, message on >= 95 % of frames),
default (automatic) parameters, a letter needing 42 carriers with the keyed check (docs/coding.md):

* Knight as shown (8 objects selected; auto, carrier "local": K=137, n_thr=12, n_robust=2, 43 carriers):
  met, for each of the 4 keys: detected at all 134 frames, message on 100 % of frames.
* Knight, skinned parts only (6 objects selected; auto: K=179, n_thr=8, n_robust=2, 55 carriers):
  detected and message at all 134 frames of these 4 actions (every action: examples/knight_parts.py).
  The same carrier as the six parts joined into one object: the join side by side changes nothing.
* Fox: NOT met, and not reachable with this method: automatic parameters refuse a letter (at most
  34 carriers); one bit needs 32 carriers (K = 100, n_thr = 1); a detectable mark needs at least 20
  carriers (P(false alarm) < 1e-6), i.e. K >= 42 bins over 290 vertices, and at K = 42 posing moves 46 % of
  the vertices' Laplacian lengths by more than half a bin per frame (p90: 2.9 bins). The mark reads
  back exactly at rest, is near chance level in motion (mean CDR 0.68-0.69), and is never detected.
"""
import json

import bpy
import numpy as np
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result
from meshmark_blender import bridge


def _play(obj, rig, kf, actions, tmp_path, step=1):
    rows = []
    for name in actions:
        act = bpy.data.actions[name]
        rig.animation_data.action = act
        s, e = (int(round(x)) for x in act.frame_range)
        rigs.select_only(obj)
        assert bpy.ops.meshmark.deformation_study(keyfile=kf, frame_start=s, frame_end=e, frame_step=step,
                                                  output_dir=str(tmp_path / name)) == {"FINISHED"}
        r = last_result()
        rows += [(name, x["frame"], x["nc"], x["cdr"], x["detected"], x["message_ok"], x["max_disp_rel"],
                  x["n_vertices"]) for x in r["rows"]]
    return rows


def _summary(name, rows, note):
    a = np.array([r[2:] for r in rows], float)
    per_action = []
    for act in dict.fromkeys(r[0] for r in rows):
        b = np.array([r[2:] for r in rows if r[0] == act], float)
        per_action.append((act, len(b), b[:, 0].mean(), b[:, 0].min(), b[:, 1].mean(), b[:, 1].min(),
                           f"{b[:, 2].mean():.0%}", f"{b[:, 3].mean():.0%}", f"{100 * b[:, 4].max():.0f}%"))
    rigs.write_table(name, ["action", "frames", "mean NC", "min NC", "mean CDR", "min CDR", "detected", "message",
                            "max disp"], per_action, note)
    return {"frames": len(a), "mean_cdr": a[:, 1].mean(), "min_cdr": a[:, 1].min(), "detected": a[:, 2].mean(),
            "message": a[:, 3].mean(), "welded_counts": set(a[:, 5].astype(int).tolist())}


def _copies_coincide(obj) -> int:
    """The welded vertex count of the base mesh (copies that moved apart would not weld)."""
    return meshmark.weld_vertices(bridge.base_mesh(obj)).mesh.n_vertices


def _wrong_key(kf, tmp_path):
    d = json.loads(open(kf).read())
    d["key"] = "not-" + d["key"]
    from meshmark.watermark.keyfile import sign_keyfile
    d = sign_keyfile(d, d["key"])  # a consistent keyfile with another key (an edited one fails its tag)
    path = tmp_path / "wrong.json"
    path.write_text(json.dumps(d))
    return str(path)


def test_fox(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Fox.glb"))
    fox, rig = bpy.data.objects["fox"], bpy.data.objects["root"]
    # the importer keeps the file's non-indexed triangles: 1728 vertices = 576 loose triangles
    assert (len(fox.data.vertices), len(fox.data.polygons)) == (1728, 576)
    assert fox.modifiers[0].type == "ARMATURE" and len(fox.vertex_groups) == 24
    assert _copies_coincide(fox) == 290  # welded: one closed surface of 290 vertices
    rigs.select_only(fox)
    bpy.ops.meshmark.capacity(method="laplacian", params="thesis")
    r = last_result()
    assert (r["n_input_vertices"], r["n_vertices"], r["params"]["K"], r["capacity"]) == (1728, 290, 5, 1)
    bpy.ops.meshmark.capacity(method="laplacian", weld=False, params="thesis")  # the loose triangles, as before welding
    assert (last_result()["n_vertices"], last_result()["capacity"]) == (1728, 7)
    kf = str(tmp_path / "fox.json")
    # default (automatic) parameters: the ladder's largest capacity is 34 carriers (K=97, n_thr=2), too
    # few for a letter (8 + 20 check bits need 42): refused, nothing changed
    with pytest.raises(RuntimeError, match="needs 42 bits, the mesh can carry 34 bits .*not even one letter fits"):
        bpy.ops.meshmark.embed(message="F", key="fox", keyfile=kf)
    # one bit (1 + 20 check bits need 32 carriers): K=100, n_thr=1, n_robust=1 give 32 with the thesis
    # carrier (with the default carrier "local" this mark does not take on the Fox for this key)
    assert bpy.ops.meshmark.embed(bits="1", key="fox", keyfile=kf, K=100, n_thr=1, n_robust=1,
                                  carrier="thesis") == {"FINISHED"}
    e = last_result()
    assert (e["capacity"], e["welded_vertices"], e["n_merged"], e["stored_cdr"]) == (32, 290, 1438, 1.0)
    assert _copies_coincide(fox) == 290  # every copy of a vertex got the same mark: no crack
    rig.data.pose_position = "REST"
    bpy.ops.meshmark.verify(keyfile=kf)
    assert last_result()["cdr"] == 1.0 and last_result()["message"] == "1"
    rig.data.pose_position = "POSE"
    rows = _play(fox, rig, kf, ["Survey", "Walk", "Run"], tmp_path)
    s = _summary("character_fox", rows, "Fox.glb (1728 vertices imported, welded to 290), Laplacian K=100 n_thr=1 "
                 "n_robust=1 (thesis defaults offer 1 carrier), 32 carriers, 1 payload bit, key 'fox', every frame")
    assert s["frames"] == 83 + 18 + 29  # Survey 0-82, Walk 0-17, Run 0-28
    assert s["welded_counts"] == {290}  # posing keeps the copies coincident (equal skin weights)
    # Measured, targets NOT met (see the module docstring): the mark is at chance level in motion and
    # is never detected: no false "found" on a mark that did not survive.
    assert s["mean_cdr"] < 0.8 and s["detected"] == 0.0 and s["message"] == 0.0, s


def _import_knight():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Knight.glb"))
    bpy.ops.object.select_all(action="DESELECT")
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    assert len(meshes) == 16  # 15 parts of the character + the importer's bone-shape icosphere
    skinned = [o for o in meshes if any(m.type == "ARMATURE" for m in o.modifiers)]
    assert sorted(o.name for o in skinned) == ["Knight_ArmLeft", "Knight_ArmRight", "Knight_Body", "Knight_Head",
                                               "Knight_LegLeft", "Knight_LegRight"]
    return skinned, bpy.data.objects["Rig"]


def _world_coords(obj) -> np.ndarray:
    m = bridge.evaluated_mesh(bpy.context, obj)
    M = np.array(obj.matrix_world)
    return m.V @ M[:3, :3].T + M[:3, 3]


def _join(parts, into):
    for o in parts:
        o.select_set(True)
    bpy.context.view_layer.objects.active = into
    bpy.ops.object.join()


ACTIONS = ["Walking_A", "1H_Melee_Attack_Chop", "Jump_Full_Long", "Spellcast_Shoot"]


def _select(objs):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0]


def test_knight_skinned_parts(addon, tmp_path):
    """The six skinned parts (body, head, arms, legs) selected and marked as one carrier, not joined:
    one keyfile that records them; Verify and the frame check read all six from any one of them."""
    skinned, rig = _import_knight()
    body = bpy.data.objects["Knight_Body"]
    rigs.select_only(body)
    bpy.ops.meshmark.capacity(method="laplacian", params="thesis")
    assert (last_result()["n_vertices"], last_result()["capacity"]) == (540, 2)  # one part alone: far too small
    rest = {o.name: rigs.base_coords(o).copy() for o in skinned}
    # marking one part alone works but says what is lost
    assert bpy.ops.meshmark.embed(message="K", key="knight", keyfile=str(tmp_path / "body.json")) == {"FINISHED"}
    assert any("only part of a character of 6 skinned objects" in w for w in last_result()["warnings"])
    body.data.vertices.foreach_set("co", rest["Knight_Body"].ravel())  # unmarked again
    body.data.update()
    _select(skinned)
    bpy.ops.meshmark.capacity(method="laplacian", params="thesis")
    r = last_result()  # the parts' flat-shading splits welded; no part welds to another
    assert (r["n_input_vertices"], r["n_vertices"], r["params"]["K"], r["capacity"]) == (3716, 2145, 31, 6)
    kf = str(tmp_path / "knight.json")
    assert bpy.ops.meshmark.embed(message="K", key="knight", keyfile=kf) == {"FINISHED"}  # default settings
    e = last_result()
    assert (e["capacity"], e["params"]["K"], e["params"]["n_thr"], e["params"]["n_robust"], e["stored_cdr"]) == \
        (55, 179, 8, 2, 1.0)
    assert e["warnings"] == [] and e["objects"] == sorted(o.name for o in skinned)
    parts = json.loads(open(kf).read())["mesh"]["parts"]
    assert [(p["object"], p["n_vertices"]) for p in parts] == [(o.name, len(o.data.vertices)) for o in
                                                                sorted(skinned, key=lambda o: o.name)]
    assert all(not np.array_equal(rigs.base_coords(o), rest[o.name]) for o in skinned)  # every part took its share
    assert {o.meshmark_keyfile for o in skinned} == {kf}
    rows = _play(body, rig, kf, ACTIONS, tmp_path)  # the body alone selected: the keyfile's six parts are read
    s = _summary("character_knight_skinned", rows, "Knight.glb, the 6 skinned parts selected, not joined (3716 "
                 "vertices imported, welded to 2145), Laplacian, automatic parameters K=179 n_thr=8 n_robust=2 "
                 "(thesis defaults offer 6 carriers), 55 carriers, message 'K', key 'knight', every frame")
    assert s["frames"] == 27 + 27 + 57 + 23 and s["welded_counts"] == {2145}
    # measured with this key (the same carrier as the six parts joined: K=179, 55 carriers): detected and
    # the message read at every frame of these four actions; every action: examples/knight_parts.py
    assert s["mean_cdr"] >= 0.95 and s["detected"] == 1.0 and s["message"] >= 0.95, s


def test_knight_as_shown(addon, tmp_path):
    """The character as it appears: the six skinned parts plus the helmet (on the head bone) and the
    cape (on the chest bone), which follow their bones rigidly, selected together and marked as one
    carrier. Each part is read in its own object space, so the helmet and cape carry their share
    unchanged by posing. The swords and shields are alternatives for the hand slots and are left out."""
    skinned, rig = _import_knight()
    extra = [bpy.data.objects["Knight_Helmet"], bpy.data.objects["Knight_Cape"]]
    assert all(o.parent == rig and o.parent_type == "BONE" for o in extra)
    parts = sorted(skinned + extra, key=lambda o: o.name)
    _select(parts)
    bpy.ops.meshmark.capacity(method="laplacian", params="thesis")
    r = last_result()
    assert (r["n_input_vertices"], r["n_vertices"], r["params"]["K"], r["capacity"]) == (4276, 2454, 36, 8)
    rest = {o.name: rigs.base_coords(o).copy() for o in parts}
    per_key = []
    for key in ("knight", "k1", "k2", "k3"):
        for o in parts:  # unmarked again
            o.data.vertices.foreach_set("co", rest[o.name].ravel())
            o.data.update()
        _select(parts)
        kf = str(tmp_path / f"knight-{key}.json")
        assert bpy.ops.meshmark.embed(message="K", key=key, keyfile=kf) == {"FINISHED"}
        e = last_result()
        assert (e["capacity"], e["params"]["K"], e["params"]["n_thr"], e["stored_cdr"]) == (43, 137, 12, 1.0)
        rows = _play(bpy.data.objects["Knight_Helmet"], rig, kf, ACTIONS, tmp_path / key)
        note = ("Knight.glb as shown: 6 skinned parts + helmet + cape selected, not joined (4276 vertices imported, "
                "welded to 2454), Laplacian, automatic parameters K=137 n_thr=12 n_robust=2 (thesis defaults offer 8 "
                f"carriers), 43 carriers, message 'K', key '{key}', every frame")
        s = _summary("character_knight" if key == "knight" else f"character_knight_{key}", rows, note)
        assert s["frames"] == 27 + 27 + 57 + 23 and s["welded_counts"] == {2454}
        per_key.append((key, s["frames"], s["mean_cdr"], s["min_cdr"], f"{s['detected']:.1%}", f"{s['message']:.1%}"))
        # targets: detected at every frame, mean CDR >= 0.9, message on >= 95 % of frames
        assert s["detected"] == 1.0 and s["mean_cdr"] >= 0.9 and s["message"] >= 0.95, (key, s)
    rigs.write_table("character_knight_keys", ["key", "frames", "mean CDR", "min CDR", "detected", "message"], per_key,
                     "Knight as shown (8 objects selected, not joined), automatic parameters (K=137 n_thr=12 "
                     "n_robust=2), 43 carriers, message 'K': one embedding per key")
    # a wrong key is never detected, at any frame (the last embedding, key k3, read with 'not-k3')
    wrong = _play(bpy.data.objects["Knight_Body"], rig, _wrong_key(kf, tmp_path), ACTIONS[:1], tmp_path / "wrong")
    assert len(wrong) == 27 and not any(r[4] for r in wrong) and not any(r[5] for r in wrong)
