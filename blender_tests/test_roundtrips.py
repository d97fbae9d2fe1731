"""(4) Round trips of a marked mesh through Blender: save and reopen the .blend; export and
reimport with Blender's own OBJ, PLY, STL, glTF and FBX exporters (default settings); apply the
armature modifier. Verify blindly with the keyfile in the rest pose. Exporters that split vertices
(UV seams, sharp normals) are handled by the core welding exactly coincident vertices."""
import os

import bpy
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result


@pytest.fixture
def marked_elephant(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = rigs.mesh_object("elephant", mesh=meshmark.read_mesh(rigs.shared_mesh("classic/elephant.off")))
    bpy.ops.object.shade_smooth()
    kf = str(tmp_path / "k.json")
    assert bpy.ops.meshmark.embed(message="E", key="trip", keyfile=kf) == {"FINISHED"}
    return obj, kf


def _verify_active(kf):
    assert bpy.ops.meshmark.verify(keyfile=kf, evaluated=False) == {"FINISHED"}
    return last_result()


def test_blend_save_and_reopen(marked_elephant, tmp_path):
    obj, kf = marked_elephant
    path = str(tmp_path / "marked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    rigs.select_only(bpy.data.objects["elephant"])
    r = _verify_active(kf)
    assert r["cdr"] == 1.0 and r["message"] == "E" and r["detected"]
    assert os.path.isfile(kf) and not bpy.data.texts  # the keyfile stayed outside the .blend


EXPORTERS = {
    "obj": (lambda p: bpy.ops.wm.obj_export(filepath=p), lambda p: bpy.ops.wm.obj_import(filepath=p)),
    "ply": (lambda p: bpy.ops.wm.ply_export(filepath=p), lambda p: bpy.ops.wm.ply_import(filepath=p)),
    "stl": (lambda p: bpy.ops.wm.stl_export(filepath=p), lambda p: bpy.ops.wm.stl_import(filepath=p)),
    "glb": (lambda p: bpy.ops.export_scene.gltf(filepath=p), lambda p: bpy.ops.import_scene.gltf(filepath=p)),
    "fbx": (lambda p: bpy.ops.export_scene.fbx(filepath=p), lambda p: bpy.ops.import_scene.fbx(filepath=p)),
}
ROWS = {}


@pytest.mark.parametrize("fmt", list(EXPORTERS))
def test_export_reimport(marked_elephant, tmp_path, fmt):
    obj, kf = marked_elephant
    path = str(tmp_path / f"marked.{fmt}")
    export, imp = EXPORTERS[fmt]
    rigs.select_only(obj)
    assert export(path) == {"FINISHED"}
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert imp(path) == {"FINISHED"}
    new = [o for o in bpy.data.objects if o.type == "MESH"]
    assert len(new) == 1
    rigs.select_only(new[0])
    n_file = len(new[0].data.vertices)
    r = _verify_active(kf)
    ROWS[fmt] = (fmt, n_file, r["n_vertices"], r["welded"], r["nc"], r["cdr"], r["message"] or "-")
    rigs.write_table("roundtrips", ["format", "vertices imported", "vertices verified", "welded", "NC", "CDR",
                                    "message"], [ROWS[k] for k in EXPORTERS if k in ROWS],
                     "elephant.off (20,007 vertices), Laplacian thesis defaults (44 carriers), message 'E'; "
                     "Blender exporters/importers with default settings, rest pose")
    assert r["cdr"] == 1.0 and r["message"] == "E" and r["detected"], r


def test_apply_armature_modifier(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    arm = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
    skel = rigs.chain_armature("Rig", [(0, 0, 0), (0, 0, 1), (0, 0, 2)])
    rigs.rig_auto(arm, skel)
    rigs.select_only(arm)
    kf = str(tmp_path / "k.json")
    bpy.ops.meshmark.embed(message="M", key="arm", keyfile=kf)
    bpy.ops.object.modifier_apply(modifier=arm.modifiers[0].name)  # rest pose: the mesh is unchanged
    assert not arm.modifiers
    r = _verify_active(kf)
    assert r["cdr"] == 1.0 and r["message"] == "M"
    # posed, then applied: the bend becomes the base mesh and the mark is still there
    rigs.pose(skel, "b1", bend_deg=30)
    arm.modifiers.new("Armature", "ARMATURE").object = skel
    rigs.select_only(arm)
    bpy.ops.object.modifier_apply(modifier="Armature")
    r = _verify_active(kf)
    assert r["cdr"] >= 0.95 and r["message"] == "M"


def test_gltf_flat_shaded_splits_and_welds(marked_elephant, tmp_path):
    """Flat shading makes the glTF exporter split every vertex per face normal; verify welds them."""
    obj, kf = marked_elephant
    bpy.ops.object.shade_flat()
    path = str(tmp_path / "flat.glb")
    assert bpy.ops.export_scene.gltf(filepath=path) == {"FINISHED"}
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    new = [o for o in bpy.data.objects if o.type == "MESH"][0]
    rigs.select_only(new)
    n_file = len(new.data.vertices)
    r = _verify_active(kf)
    rigs.write_table("roundtrip_gltf_flat", ["format", "vertices imported", "vertices verified", "welded", "NC",
                                             "CDR", "message"],
                     [("glb, flat shaded", n_file, r["n_vertices"], r["welded"], r["nc"], r["cdr"], r["message"])])
    assert n_file > 20007 and r["welded"] and r["n_vertices"] == 20007
    assert r["cdr"] == 1.0 and r["message"] == "E"
