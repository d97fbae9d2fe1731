"""(3) The real rigged characters: import with Blender's glTF importer, embed into the skinned mesh,
play the animations and verify at every frame with the deformation-study operator.

Both characters are far below the size the thesis' Laplacian method is made for (§7.4 uses
K = ceil(N/70) bins with at least 46 elements per pair): at thesis defaults the Fox offers 7
carrier bits and the joined Knight 10, fewer than one framed text byte (24 bits). The test uses the
smallest parameters that fit a one-letter message and records what survives (build/blender-results).
Measured: the Knight (rigid-ish parts) keeps CDR ~0.98 on average but is not detected on every
frame; the Fox (576 loose triangles, smoothly skinned) does not keep the mark (CDR ~0.5): the
targets "detected at every frame, CDR >= 0.9, message on >= 95% of frames" are not met.
"""
import bpy
import numpy as np
import pytest

from blender_tests import rigs
from blender_tests.rigs import last_result


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
        rows += [(name, x["frame"], x["nc"], x["cdr"], x["detected"], x["message_ok"], x["max_disp_rel"])
                 for x in r["rows"]]
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
    return {"frames": len(a), "mean_cdr": a[:, 1].mean(), "detected": a[:, 2].mean(), "message": a[:, 3].mean()}


def test_fox(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Fox.glb"))
    fox, rig = bpy.data.objects["fox"], bpy.data.objects["root"]
    # the importer keeps the file's non-indexed triangles: 1728 vertices = 576 loose triangles
    assert (len(fox.data.vertices), len(fox.data.polygons)) == (1728, 576)
    assert fox.modifiers[0].type == "ARMATURE" and len(fox.vertex_groups) == 24
    rigs.select_only(fox)
    bpy.ops.meshmark.capacity(method="laplacian")
    assert last_result()["capacity"] == 7  # thesis defaults (K = 25): too small
    kf = str(tmp_path / "fox.json")
    assert bpy.ops.meshmark.embed(message="F", key="fox", keyfile=kf, K=80, n_thr=8) == {"FINISHED"}
    assert last_result()["capacity"] == 28
    rig.data.pose_position = "REST"
    bpy.ops.meshmark.verify(keyfile=kf)
    assert last_result()["cdr"] == 1.0 and last_result()["message"] == "F"
    rig.data.pose_position = "POSE"
    rows = _play(fox, rig, kf, ["Survey", "Walk", "Run"], tmp_path)
    s = _summary("character_fox", rows, "Fox.glb (1728 vertices, 576 loose triangles), Laplacian K=80 n_thr=8 "
                 "(thesis defaults offer 7 carriers), 28 carriers, message 'F', every frame of each action")
    assert s["frames"] == 83 + 18 + 29  # Survey 0-82, Walk 0-17, Run 0-28
    # Measured, target NOT met: 576 loose triangles give each vertex a 2-neighbour "Laplacian" that the
    # skinning changes by 1-13 %, so the 28 bits are at chance level (mean CDR ~0.5) and never detected.
    # The check below pins that: no false "found" on a mark that did not survive.
    assert s["mean_cdr"] < 0.8 and s["detected"] == 0.0, s


def test_knight(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Knight.glb"))
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    assert len(meshes) == 16  # 15 parts of the character + the importer's bone-shape icosphere
    skinned = [o for o in meshes if any(m.type == "ARMATURE" for m in o.modifiers)]
    assert sorted(o.name for o in skinned) == ["Knight_ArmLeft", "Knight_ArmRight", "Knight_Body", "Knight_Head",
                                               "Knight_LegLeft", "Knight_LegRight"]
    rigs.select_only(bpy.data.objects["Knight_Body"])
    bpy.ops.meshmark.capacity(method="laplacian")
    assert last_result()["capacity"] < 8  # one part alone (1141 vertices) is far too small
    # the skinned parts joined into one mesh (vertex groups and the armature modifier are kept)
    for o in skinned:
        o.select_set(True)
    bpy.ops.object.join()
    knight, rig = bpy.data.objects["Knight_Body"], bpy.data.objects["Rig"]
    assert len(knight.data.vertices) == 3716 and knight.modifiers[0].type == "ARMATURE"
    bpy.ops.meshmark.capacity(method="laplacian")
    assert last_result()["capacity"] == 10
    kf = str(tmp_path / "knight.json")
    assert bpy.ops.meshmark.embed(message="K", key="knight", keyfile=kf, K=100, n_thr=4, n_robust=1) == {"FINISHED"}
    assert last_result()["capacity"] == 27
    rows = _play(knight, rig, kf, ["Walking_A", "1H_Melee_Attack_Chop", "Jump_Full_Long", "Spellcast_Shoot"], tmp_path)
    s = _summary("character_knight", rows, "Knight.glb, 6 skinned parts joined (3716 vertices), Laplacian K=100 "
                 "n_thr=4 n_robust=1 (thesis defaults offer 10 carriers), 27 carriers, message 'K', every frame")
    assert s["frames"] >= 24
    assert s["mean_cdr"] >= 0.95 and s["detected"] >= 0.7, s  # measured; target (every frame) not met
