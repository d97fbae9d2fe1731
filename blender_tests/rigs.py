"""Building, rigging and posing test scenes in Blender (shared by the Blender tests and the demo's
checks). Everything goes through bpy operators and data as an artist's scene would."""
from __future__ import annotations

import math
import os
import sys

import bpy
import numpy as np
from mathutils import Euler, Vector

import meshmark
from meshmark.shapes import cylinder

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
SHARED = os.path.join(ROOT, "..", "shared", "meshes")
RESULTS = os.path.join(ROOT, "build", "blender-results")


def shared_mesh(rel: str) -> str:
    path = os.path.normpath(os.path.join(SHARED, rel))
    if not os.path.exists(path):  # tests that need ../shared/meshes fail, never skip
        raise FileNotFoundError(f"shared mesh missing: {path}")
    return path


def study_spec(mesh_path: str, seeds=(0,), attacks=(), name: str = "blender") -> str:
    """A small study spec (TOML text) for the add-on's study operator: Cho mean on one mesh, the attack
    ``none`` plus ``attacks`` (TOML ``[[attacks]]`` bodies, e.g. ``'name = "noise"\ngrid = { strength = [0.001] }'``),
    NC and detection. Tasks: len(seeds) x (1 + len(attacks)) x grid points."""
    blocks = "".join(f"[[attacks]]\n{a}\n" for a in ('name = "none"', *attacks))
    return (f'[study]\nname = "{name}"\nseeds = {list(seeds)}\npayload_bits = 8\n[meshes]\npaths = ["{mesh_path}"]\n'
            f'[[methods]]\nname = "cho-mean"\n{blocks}[measurements]\nlist = ["nc", "detection"]\n')


def mesh_object(name: str, V=None, F=None, mesh: meshmark.Mesh | None = None):
    """A new mesh object (linked to the scene, active and selected) from arrays, via foreach_set."""
    m = mesh if mesh is not None else meshmark.Mesh(V, F)
    me = bpy.data.meshes.new(name)
    n, nf, nc = m.n_vertices, m.n_faces, m.face_indices.size
    me.vertices.add(n)
    me.vertices.foreach_set("co", m.V.astype(np.float32).ravel())
    me.loops.add(nc)
    me.loops.foreach_set("vertex_index", m.face_indices)
    me.polygons.add(nf)
    me.polygons.foreach_set("loop_start", m.face_offsets[:-1].astype(np.int32))
    if bpy.app.version < (4, 0, 0):  # before 4.0 the polygon sizes are stored, not derived
        me.polygons.foreach_set("loop_total", np.diff(m.face_offsets).astype(np.int32))
    me.update(calc_edges=True)
    me.validate()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    select_only(obj)
    return obj


def select_only(obj):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def jittered_arm(seed: int = 0):
    """The arm of tests/test_laplacian_watermark.py: a 64 x 320 tube (20,482 vertices) along +z,
    length 2, jittered by 0.25 x the ring spacing so that its Laplacian lengths spread."""
    m = cylinder(segments=64, rings=320)
    h = 2 * np.pi * 0.15 / 64
    return m.with_vertices(m.V + np.random.default_rng(seed).uniform(-0.25, 0.25, m.V.shape) * h)


def chain_armature(name: str, points) -> bpy.types.Object:
    """An armature whose bones run through ``points`` (each bone parented and connected to the
    previous one), bone names ``b0, b1, ...``."""
    arm = bpy.data.armatures.new(name)
    ob = bpy.data.objects.new(name, arm)
    bpy.context.scene.collection.objects.link(ob)
    select_only(ob)
    bpy.ops.object.mode_set(mode="EDIT")
    prev = None
    for i in range(len(points) - 1):
        b = arm.edit_bones.new(f"b{i}")
        b.head, b.tail = Vector(points[i]), Vector(points[i + 1])
        if prev is not None:
            b.parent, b.use_connect = prev, True
        prev = b
    bpy.ops.object.mode_set(mode="OBJECT")
    return ob


def rig_auto(mesh_obj, arm_obj) -> np.ndarray:
    """Parent with automatic (bone heat) weights; returns the (n,) total weight per vertex."""
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    mesh_obj.select_set(True)
    arm_obj.select_set(True)
    bpy.context.view_layer.objects.active = arm_obj
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    return vertex_weight_sums(mesh_obj)


def vertex_weight_sums(obj) -> np.ndarray:
    w = np.zeros(len(obj.data.vertices))
    for v in obj.data.vertices:  # test-side check only (the add-on never loops over vertices)
        w[v.index] = sum(g.weight for g in v.groups)
    return w


def pca_chain(mesh: meshmark.Mesh, n_bones: int = 2):
    """Points of a bone chain along the mesh's first principal axis, spanning its extent."""
    p = meshmark.pca(mesh.V)
    c, q = np.asarray(p["centroid"]), np.asarray(p["axes"])[:, 0]
    t = (mesh.V - c) @ q
    return [c + q * s for s in np.linspace(t.min() * 0.98, t.max() * 0.98, n_bones + 1)]


def pose(arm_obj, bone: str, bend_deg: float = 0.0, twist_deg: float = 0.0, bend_axis: str = "X"):
    """Rotate a pose bone: bend about its local X (or Z) axis, twist about its own (Y) axis."""
    pb = arm_obj.pose.bones[bone]
    pb.rotation_mode = "XYZ"
    e = [0.0, math.radians(twist_deg), 0.0]
    e["XYZ".index(bend_axis)] = math.radians(bend_deg)
    pb.rotation_euler = Euler(e, "XYZ")
    bpy.context.view_layer.update()


def base_coords(obj) -> np.ndarray:
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def last_result():
    import json
    return json.loads(bpy.context.scene.meshmark.last_result)


def write_table(name: str, header: list, rows: list, note: str = "") -> str:
    """Write a markdown table of measured figures to build/blender-results/NAME.md and print it."""
    os.makedirs(RESULTS, exist_ok=True)
    fmt = lambda v: f"{v:.3f}" if isinstance(v, float) else str(v)
    lines = ([note, ""] if note else []) + ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(fmt(v) for v in r) + " |" for r in rows]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(RESULTS, name + ".md"), "w") as f:
        f.write(text)
    print(f"\n[{name}]\n{text}")
    return text


def bend_over_frames(rig, bone, frames, degrees, turn=None):
    """Keyframe ``bone``: a bend of ``degrees[i]`` (and a turn about Z of ``turn[i]``) at ``frames[i]``."""
    pb = rig.pose.bones[bone]
    pb.rotation_mode = "XYZ"
    for i, (f, deg) in enumerate(zip(frames, degrees)):
        pb.rotation_euler = (math.radians(deg), 0.0, math.radians(turn[i]) if turn else 0.0)
        pb.keyframe_insert("rotation_euler", frame=f)


def suzanne_subdivided_and_rigged():
    """Suzanne with an unapplied Subdivision (level 2) and a neck and head rig, animated over frames
    1-48 (the neck nods 8 degrees, the head nods 20 and turns 40 each way): (object, modifier, rig)."""
    bpy.ops.mesh.primitive_monkey_add()
    suz = bpy.context.active_object
    sub = suz.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = 2
    rig = chain_armature("Rig", [(0, 0, -1.6), (0, 0, -0.9), (0, 0, 1.0)])  # neck, head
    rig_auto(suz, rig)
    keys = (1, 12, 24, 36, 48)
    bend_over_frames(rig, "b0", keys, (0, 8, 0, -8, 0))
    bend_over_frames(rig, "b1", keys, (0, 20, 0, -20, 0), turn=(0, 40, 0, -40, 0))
    select_only(suz)
    return suz, sub, rig


def secret_needles(text: str, key: str) -> dict:
    """What must never be found in a saved file: the text, its hex (lower, upper, the first 64 bytes)
    and the key, each in UTF-8, UTF-16LE and UTF-16BE."""
    data = text.encode()
    hexes = [data.hex(), data.hex().upper(), data[:64].hex()]
    out = {}
    for name, s in [("text", text), ("key", key)] + [(f"hex{i}", h) for i, h in enumerate(hexes)]:
        for enc in ("utf-8", "utf-16-le", "utf-16-be"):
            out[f"{name}/{enc}"] = s.encode(enc)
    return out


def bridge_faces(obj):
    from meshmark_blender import bridge
    return bridge.faces(obj.data)


def skin_to_parent_bone(obj, rig):
    """Turn an object parented to a bone into a mesh skinned to that bone with weight 1 (the same
    rigid motion, now through the armature modifier, so that it can be joined to the skinned body)."""
    bone = obj.parent_bone
    assert obj.parent == rig and obj.parent_type == "BONE"
    rig.data.pose_position = "REST"  # the armature modifier deforms from the rest placement
    bpy.context.view_layer.update()
    world = obj.matrix_world.copy()
    obj.parent = None
    obj.matrix_world = world
    rig.data.pose_position = "POSE"
    obj.vertex_groups.new(name=bone).add(list(range(len(obj.data.vertices))), 1.0, "REPLACE")
    obj.modifiers.new("Armature", "ARMATURE").object = rig
