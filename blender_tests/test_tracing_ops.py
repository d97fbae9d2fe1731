"""bpy.ops.meshmark.issue_copies / trace (copy tracing from Blender)."""
import json

import bpy
import numpy as np

import meshmark
from blender_tests import rigs


def test_issue_copies_and_trace_one(addon, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    src = meshmark.read_mesh(rigs.shared_mesh("classic/fandisk.obj"))
    obj = rigs.mesh_object("fandisk", mesh=src)
    co0 = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co0)
    reg = str(tmp_path / "r.sqlite")
    assert bpy.ops.meshmark.issue_copies(copies=3, key="studio", registry=reg, output_dir=str(tmp_path)) == {"FINISHED"}
    made = json.loads(bpy.context.scene.meshmark.last_result)["copies"]
    assert [c["id"] for c in made] == ["0001", "0002", "0003"]
    co1 = np.empty_like(co0)
    obj.data.vertices.foreach_get("co", co1)
    assert np.array_equal(co0, co1)  # the object itself is not changed
    # the untouched object: none; a copy read back into Blender (float32): its id
    assert bpy.ops.meshmark.trace(registry=reg) == {"FINISHED"}
    assert json.loads(bpy.context.scene.meshmark.last_result)["copy"] is None
    rigs.mesh_object("leak", mesh=meshmark.read_mesh(made[1]["path"]))
    assert bpy.ops.meshmark.trace(registry=reg) == {"FINISHED"}
    r = json.loads(bpy.context.scene.meshmark.last_result)
    assert r["copy"] == "0002" and r["p_false_alarm"] < 1e-6
