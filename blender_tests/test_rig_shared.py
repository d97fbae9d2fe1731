"""(2) Meshes from ../shared/meshes rigged in the test: a two-bone armature along the mesh's first
principal axis, automatic weights, posed (bends about the joint and a twist); NC/CDR per pose.
The Hand is the thesis' own deformation example (Table 7.2: NC 0.93 and 0.73 for its two
deformations): the mark fades as the bend grows."""
import bpy
import pytest

import meshmark
from blender_tests import rigs
from blender_tests.rigs import last_result

POSES = [(0, 0), (5, 0), (10, 0), (15, 0), (20, 0), (30, 0), (45, 0), (60, 0), (90, 0), (0, 45), (15, 15)]

CASES = {
    # name: (file, how to import, params, message)
    # 21 carriers at thesis defaults: no room for a text byte (24-bit frame), so 4 raw bits (20)
    "hand": ("classic/hand.obj", "obj", {"bits": "1011"}, "1011"),
    "elephant": ("classic/elephant.off", "meshmark", {}, "E"),  # 44 carriers at thesis defaults
}


def _import(rel, how):
    path = rigs.shared_mesh(rel)
    if how == "obj":
        bpy.ops.wm.obj_import(filepath=path)
        return bpy.context.active_object
    return rigs.mesh_object(rel.split("/")[-1].split(".")[0], mesh=meshmark.read_mesh(path))  # Blender reads no OFF


@pytest.mark.parametrize("name", list(CASES))
def test_rigged_shared_mesh(addon, tmp_path, name):
    rel, how, params, msg = CASES[name]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = _import(rel, how)
    base = meshmark.Mesh.from_polygons(rigs.base_coords(obj).astype(float), *rigs.bridge_faces(obj))
    skel = rigs.chain_armature("Rig", rigs.pca_chain(base, 2))
    w = rigs.rig_auto(obj, skel)
    assert (w > 0).mean() > 0.99, f"{(w == 0).sum()} vertices without weights"
    rigs.select_only(obj)
    bpy.ops.meshmark.capacity(method="laplacian")
    cap_default = last_result()["capacity"]
    kf = str(tmp_path / f"{name}.json")
    assert bpy.ops.meshmark.embed(message=msg, key=name, keyfile=kf, **params) == {"FINISHED"}
    e = last_result()
    rows = []
    for bend, twist in POSES:
        rigs.pose(skel, "b1", bend_deg=bend, twist_deg=twist)
        rigs.select_only(obj)
        bpy.ops.meshmark.verify(keyfile=kf)
        r = last_result()
        rows.append((bend, twist, r["nc"], r["cdr"], r["detected"], r["message"] if r["message_ok"] else "-"))
    rigs.pose(skel, "b1")
    rigs.write_table(f"shared_{name}", ["bend deg", "twist deg", "NC", "CDR", "detected", "message"], rows,
                     f"{rel} ({len(obj.data.vertices)} vertices), PCA two-bone rig, automatic weights; "
                     f"capacity {cap_default} at thesis defaults; embedded with {params or 'thesis defaults'}: "
                     f"{e['capacity']} carriers, message {msg!r}")
    by = {(b, t): r for b, t, *r in rows}
    assert by[(0, 0)][1] == 1.0 and by[(0, 0)][3] == msg
    assert all(by[(b, 0)][2] and by[(b, 0)][3] == msg for b in (5, 10, 15)), rows  # moderate bends
    nc = [by[(b, 0)][0] for b in (0, 30, 60, 90)]
    assert nc[0] >= nc[-1], nc  # the contrast of Table 7.2: stronger deformation, lower NC
