"""The main job, end to end in Blender: watermark a rigged character, animate it, verify every frame.

    python examples/blender_demo.py                      # built-in character, no files needed
    python examples/blender_demo.py --mesh my.obj        # your mesh (OBJ/PLY/STL/glTF/FBX/OFF), auto-rigged
    python examples/blender_demo.py --mesh shot.blend --object Body   # your rigged, animated .blend
    python examples/blender_demo.py --mesh shot.blend --keyfile k.json # verify an earlier mark only

Without --mesh it builds a character-like mesh (a skin-modifier body, subdivided) with an armature
from Blender's "Create Armature from Skin" and automatic weights. The mark is embedded with the
add-on's operator (bpy.ops.meshmark.embed), a pose sweep is keyframed (arms, legs and spine bend up
to --max-angle degrees), the deformation-study operator verifies every frame, and the demo prints a
table and writes the keyfile, a CSV and a plot to --out. Runs with the `bpy` module (Blender 4.2+)
or inside Blender: ``blender --background --python examples/blender_demo.py -- [options]``.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "addon"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import meshmark_blender  # noqa: E402
from meshmark_blender import study  # noqa: E402

# Stick figure for the built-in character: joint positions (metres) and skin radii.
JOINTS = {"pelvis": ((0, 0, 1.0), .16), "chest": ((0, 0, 1.45), .2), "neck": ((0, 0, 1.65), .07),
          "head": ((0, 0, 1.9), .14),
          "l_sh": ((.22, 0, 1.55), .08), "l_el": ((.5, 0, 1.55), .06), "l_wr": ((.75, 0, 1.55), .045),
          "r_sh": ((-.22, 0, 1.55), .08), "r_el": ((-.5, 0, 1.55), .06), "r_wr": ((-.75, 0, 1.55), .045),
          "l_hip": ((.12, 0, .95), .1), "l_kn": ((.13, 0, .5), .07), "l_an": ((.14, 0, .08), .05),
          "r_hip": ((-.12, 0, .95), .1), "r_kn": ((-.13, 0, .5), .07), "r_an": ((-.14, 0, .08), .05)}
LIMBS = [("pelvis", "chest"), ("chest", "neck"), ("neck", "head"), ("chest", "l_sh"), ("l_sh", "l_el"),
         ("l_el", "l_wr"), ("chest", "r_sh"), ("r_sh", "r_el"), ("r_el", "r_wr"), ("pelvis", "l_hip"),
         ("l_hip", "l_kn"), ("l_kn", "l_an"), ("pelvis", "r_hip"), ("r_hip", "r_kn"), ("r_kn", "r_an")]


def log(msg):
    print(f"meshmark demo: {msg}", flush=True)


def select_only(obj):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def auto_rig(obj, arm):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    arm.select_set(True)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")


def build_character(levels: int = 4, seed: int = 0):
    """A character-like mesh (skin modifier over a stick figure, subdivided) and its armature."""
    names = list(JOINTS)
    me = bpy.data.meshes.new("Character")
    me.from_pydata([JOINTS[n][0] for n in names], [(names.index(a), names.index(b)) for a, b in LIMBS], [])
    obj = bpy.data.objects.new("Character", me)
    bpy.context.scene.collection.objects.link(obj)
    select_only(obj)
    obj.modifiers.new("Skin", "SKIN")
    for n, sv in zip(names, me.skin_vertices[0].data):
        sv.radius = (JOINTS[n][1], JOINTS[n][1])
    me.skin_vertices[0].data[names.index("pelvis")].use_root = True
    sub = obj.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = sub.render_levels = levels
    bpy.ops.object.skin_armature_create(modifier="Skin")  # Blender's own bones along the limbs
    arm = next(o for o in bpy.data.objects if o.type == "ARMATURE")
    for m in [m for m in obj.modifiers if m.type == "ARMATURE"]:
        obj.modifiers.remove(m)
    select_only(obj)
    bpy.ops.object.modifier_apply(modifier="Skin")
    bpy.ops.object.modifier_apply(modifier="Subdivision")
    obj.vertex_groups.clear()
    # a little sculpted irregularity (0.3 mm), as a real model has; a perfectly smooth procedural
    # surface gives the Laplacian histogram almost no spread
    co = np.empty(3 * len(me.vertices), np.float32)
    me.vertices.foreach_get("co", co)
    co += np.random.default_rng(seed).uniform(-3e-4, 3e-4, co.size).astype(np.float32)
    me.vertices.foreach_set("co", co)
    me.update()
    auto_rig(obj, arm)
    return obj, arm


def pca_armature(obj):
    """A three-bone chain along the mesh's first principal axis (for a user's unrigged mesh)."""
    import meshmark
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    V = co.reshape(-1, 3)
    p = meshmark.pca(V)
    c, q = np.asarray(p["centroid"]), np.asarray(p["axes"])[:, 0]
    t = (V - c) @ q
    pts = [obj.matrix_world @ __import__("mathutils").Vector(c + q * s) for s in np.linspace(t.min(), t.max(), 4)]
    arm = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(arm)
    select_only(arm)
    bpy.ops.object.mode_set(mode="EDIT")
    prev = None
    for i in range(3):
        b = arm.data.edit_bones.new(f"Bone.{i}")
        b.head, b.tail = pts[i], pts[i + 1]
        if prev:
            b.parent, b.use_connect = prev, True
        prev = b
    bpy.ops.object.mode_set(mode="OBJECT")
    auto_rig(obj, arm)
    return arm


def keyframe_sweep(arm, frames: int, max_angle: float):
    """Keyframe a pose sweep: every bone bends from 0 to max_angle (alternating axes) and back."""
    pbs = list(arm.pose.bones)
    half = max(1, frames // 2)
    for pb in pbs:
        pb.rotation_mode = "XYZ"
    for f in range(1, frames + 1):
        a = math.radians(max_angle) * (1 - abs(f - 1 - half) / half)
        for i, pb in enumerate(pbs):
            if pb.parent is None:
                continue
            axis = i % 3 if i % 3 != 1 else 2  # bend about x or z, never twist
            e = [0.0, 0.0, 0.0]
            e[axis] = a * (1 if i % 2 else -1) * 0.6
            pb.rotation_euler = e
            pb.keyframe_insert("rotation_euler", frame=f)
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = 1, frames


def load_user_mesh(path: str, object_name: str | None):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".blend":
        bpy.ops.wm.open_mainfile(filepath=path)
        meshes = [o for o in bpy.data.objects if o.type == "MESH"]
        obj = bpy.data.objects.get(object_name) if object_name else max(meshes, key=lambda o: len(o.data.vertices))
        if obj is None or obj.type != "MESH":
            raise SystemExit(f"meshmark demo: no mesh object {object_name!r} in {path}")
        return obj
    bpy.ops.wm.read_factory_settings(use_empty=True)
    importers = {".obj": bpy.ops.wm.obj_import, ".ply": bpy.ops.wm.ply_import, ".stl": bpy.ops.wm.stl_import,
                 ".glb": bpy.ops.import_scene.gltf, ".gltf": bpy.ops.import_scene.gltf, ".fbx": bpy.ops.import_scene.fbx}
    if ext == ".off":  # Blender has no OFF importer: read with meshmark
        import meshmark
        m = meshmark.read_mesh(path)
        me = bpy.data.meshes.new(os.path.basename(path))
        me.vertices.add(m.n_vertices)
        me.vertices.foreach_set("co", m.V.astype(np.float32).ravel())
        me.loops.add(m.face_indices.size)
        me.loops.foreach_set("vertex_index", m.face_indices)
        me.polygons.add(m.n_faces)
        me.polygons.foreach_set("loop_start", m.face_offsets[:-1].astype(np.int32))
        if bpy.app.version < (4, 0, 0):  # before 4.0 the polygon sizes are stored, not derived
            me.polygons.foreach_set("loop_total", np.diff(m.face_offsets).astype(np.int32))
        me.update(calc_edges=True)
        obj = bpy.data.objects.new(me.name, me)
        bpy.context.scene.collection.objects.link(obj)
        return obj
    if ext not in importers:
        raise SystemExit(f"meshmark demo: cannot read {path!r} (use .blend, .obj, .ply, .stl, .glb, .gltf, .fbx, .off)")
    importers[ext](filepath=path)
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    return bpy.data.objects.get(object_name) if object_name else max(meshes, key=lambda o: len(o.data.vertices))


def result():
    return json.loads(bpy.context.scene.meshmark.last_result)


def main(argv=None):
    if argv is None:
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    ap = argparse.ArgumentParser(prog="demo.sh", description=__doc__.split("\n\n")[0])
    ap.add_argument("--mesh", help="your mesh file or .blend (default: the built-in character)")
    ap.add_argument("--object", help="mesh object to use in a .blend/glTF/FBX (default: the largest)")
    ap.add_argument("--keyfile", help="verify with this keyfile instead of embedding (if it exists), "
                                      "or where to write the new keyfile")
    ap.add_argument("--message", default="ACME", help="text to hide (default: ACME)")
    ap.add_argument("--key", default="demo-key", help="secret key (default: demo-key)")
    ap.add_argument("--frames", type=int, default=48, help="frames of the pose sweep (default 48)")
    ap.add_argument("--max-angle", type=float, default=40.0, help="largest bend in degrees (default 40)")
    ap.add_argument("--out", default="meshmark-demo", help="output directory (default ./meshmark-demo)")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    try:
        meshmark_blender.register()
    except ValueError:  # already registered (running inside a Blender that has the add-on)
        pass

    if a.mesh:
        obj = load_user_mesh(a.mesh, a.object)
        arm = obj.find_armature()
        animated = arm is not None and arm.animation_data is not None and arm.animation_data.action is not None
        if arm is None:
            log(f"'{obj.name}' has no armature: rigging it along its principal axis (automatic weights)")
            arm = pca_armature(obj)
        if not animated:
            keyframe_sweep(arm, a.frames, a.max_angle)
        what = f"{a.mesh} ('{obj.name}', {len(obj.data.vertices):,} vertices)"
    else:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        obj, arm = build_character()
        keyframe_sweep(arm, a.frames, a.max_angle)
        what = f"built-in character ({len(obj.data.vertices):,} vertices, {len(arm.data.bones)} bones)"
    log(f"{what}, built/loaded in {time.perf_counter() - t0:.1f} s")

    keyfile = os.path.abspath(a.keyfile) if a.keyfile else os.path.join(out, "keyfile.json")
    scene = bpy.context.scene
    if a.keyfile and os.path.isfile(keyfile):
        log(f"verifying with the existing keyfile {keyfile} (no embedding)")
    else:
        scene.frame_set(scene.frame_start)
        select_only(obj)
        t = time.perf_counter()
        # automatic parameters (the add-on's default, meshmark.watermark.auto): no search of our own;
        # the demo's own keyfile in --out is replaced on a re-run, a --keyfile given is never replaced
        bpy.ops.meshmark.embed(method="laplacian", message=a.message, key=a.key, keyfile=keyfile, params="auto",
                               overwrite=not a.keyfile)
        e = result()
        log(f"embedded {a.message!r} in {time.perf_counter() - t:.2f} s: {e['capacity']} carrier bits, "
            f"params {e['params']} ({e['params_choice']}), max displacement {100 * e['max_disp_rel']:.3f}% of the diagonal; "
            f"keyfile {keyfile}")
    select_only(obj)
    t = time.perf_counter()
    bpy.ops.meshmark.deformation_study(keyfile=keyfile, frame_start=scene.frame_start, frame_end=scene.frame_end,
                                       frame_step=1, output_dir=out)
    r = result()
    print(study.format_table(r["rows"]))
    s = r["summary"]
    log(f"verified {s['frames']} frames in {time.perf_counter() - t:.1f} s: detected on {s['detected_frames']}, "
        f"message recovered on {s['message_frames']}, mean NC {s['mean_nc']:.3f} (min {s['min_nc']:.3f}), "
        f"mean CDR {s['mean_cdr']:.3f} (min {s['min_cdr']:.3f}), largest deformation "
        f"{100 * s['max_disp_rel']:.1f}% of the bounding-box diagonal")
    log(f"wrote {r['csv']}" + (f" and {r['plot']}" if r["plot"] else " (no plot: matplotlib missing)"))
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "demo.blend"))
    log(f"scene saved to {os.path.join(out, 'demo.blend')}; total {time.perf_counter() - t0:.1f} s")
    return 0 if s["detected_frames"] == s["frames"] else 1


if __name__ == "__main__":
    sys.exit(main())
