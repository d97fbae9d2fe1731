"""Smoke test inside a real Blender binary (e.g. Debian's 3.4, legacy add-on path):

    PYTHONPATH=src blender --background --factory-startup --python-exit-code 1 --python tools/blender_smoke.py

Registers addon/meshmark_blender as a legacy add-on, rigs the jittered arm with automatic weights,
embeds through bpy.ops.meshmark.embed, verifies at 0/30/60 degrees, runs the deformation study,
imports the rigged Fox with this Blender's glTF importer (576 loose triangles, welded by the core to
290 vertices), marks it and reads it back at rest, and unregisters. Exits non-zero (an exception) on
any failure. Needs ../shared/meshes beside the repository (for the Fox).
"""
import json
import math
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "blender_tests"))

import bpy  # noqa: E402

import meshmark_blender  # noqa: E402
import rigs  # noqa: E402

print("meshmark smoke: Blender", bpy.app.version_string)
meshmark_blender.register()
bpy.ops.wm.read_factory_settings(use_empty=True)
arm = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
skel = rigs.chain_armature("Rig", [(0, 0, 0), (0, 0, 1), (0, 0, 2)])
w = rigs.rig_auto(arm, skel)
assert (w > 0).all()
tmp = tempfile.mkdtemp()
kf = os.path.join(tmp, "k.json")
rigs.select_only(arm)
assert bpy.ops.meshmark.embed(method="laplacian", message="M", key="arm", keyfile=kf) == {"FINISHED"}
for deg in (0, 30, 60):
    rigs.pose(skel, "b1", bend_deg=deg)
    rigs.select_only(arm)
    bpy.ops.meshmark.verify(keyfile=kf, evaluated=True)
    r = json.loads(bpy.context.scene.meshmark.last_result)
    print(f"meshmark smoke: bend {deg:2d} deg  NC {r['nc']:.3f}  CDR {r['cdr']:.3f}  message {r['message']!r}")
    assert r["detected"] and r["cdr"] >= 0.95 and r["message"] == "M", r
pb = skel.pose.bones["b1"]
for f, deg in ((1, 0), (5, 60)):
    pb.rotation_euler = (math.radians(deg), 0, 0)
    pb.keyframe_insert("rotation_euler", frame=f)
rigs.select_only(arm)
assert bpy.ops.meshmark.deformation_study(keyfile=kf, frame_start=1, frame_end=5, output_dir=tmp) == {"FINISHED"}
s = json.loads(bpy.context.scene.meshmark.last_result)
print("meshmark smoke: study", s["summary"], s["csv"], s["plot"])
assert s["summary"]["detected_frames"] == 5
try:
    bpy.ops.meshmark.embed(message="M" * 40, key="k", keyfile=kf, overwrite=True)
    raise AssertionError("a too-long message was accepted")
except RuntimeError as exc:
    print("meshmark smoke: error reported as expected:", str(exc).strip()[:80])

# The rigged Fox through this Blender's own glTF importer. Blender 3.4's importer uses numpy.bool,
# which numpy 1.24 removed (an alias of bool, restored in numpy 2).
import numpy  # noqa: E402
if not hasattr(numpy, "bool"):
    numpy.bool = bool
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Fox.glb"))
fox = bpy.data.objects["fox"]
rigs.select_only(fox)
# a second keyfile: the first is never overwritten silently (docs/coding.md); one bit (1 + 20 check
# bits need 32 carriers: K=100, n_thr=1 give 32 on the Fox's 290 welded vertices with the thesis
# carrier; with the default carrier "local" the mark does not take on this mesh for this key)
kf = kf.replace(".json", "-fox.json")
assert bpy.ops.meshmark.embed(bits="1", key="fox", keyfile=kf, K=100, n_thr=1, n_robust=1,
                              carrier="thesis") == {"FINISHED"}
r = json.loads(bpy.context.scene.meshmark.last_result)
print(f"meshmark smoke: Fox {r['n_vertices']} vertices welded to {r['welded_vertices']}, {r['capacity']} carriers")
assert (r["n_vertices"], r["welded_vertices"], r["capacity"], r["stored_cdr"]) == (1728, 290, 32, 1.0), r
bpy.data.objects["root"].data.pose_position = "REST"
bpy.ops.meshmark.verify(keyfile=kf)
r = json.loads(bpy.context.scene.meshmark.last_result)
print(f"meshmark smoke: Fox at rest  CDR {r['cdr']:.3f}  message {r['message']!r}  welded {r['n_merged']} copies")
assert r["cdr"] == 1.0 and r["message"] == "1" and r["n_vertices"] == 290 and r["n_merged"] == 1438, r
meshmark_blender.unregister()
print("meshmark smoke: OK")
