"""Shared bits of the add-on examples (blender_*.py): the add-on, a mesh object, a JSON result.

Run them with the bpy module (``python examples/blender_embed.py``) or inside Blender
(``blender --background --python examples/blender_embed.py -- [options]``).
"""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "addon"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402


def argv():
    """The script's own arguments (after ``--`` inside Blender)."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]


def start(blend=None):
    """Register the add-on (if no other copy is enabled) and open ``blend`` or an empty scene."""
    import meshmark_blender
    if blend:
        bpy.ops.wm.open_mainfile(filepath=blend)
    else:
        bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "meshmark"):
        meshmark_blender.register()


def mesh_object(path=None, name="Mesh"):
    """A mesh object from a file read by meshmark (OBJ/OFF/PLY/STL), or a jittered 64 x 320 tube
    (20,482 vertices), made active and selected."""
    import meshmark
    from meshmark.shapes import cylinder
    if path:
        m = meshmark.read_mesh(path)
        name = os.path.splitext(os.path.basename(path))[0]
    else:
        m = cylinder(segments=64, rings=320)
        m = m.with_vertices(m.V + np.random.default_rng(0).uniform(-0.25, 0.25, m.V.shape) * 2 * np.pi * 0.15 / 64)
    me = bpy.data.meshes.new(name)
    me.vertices.add(m.n_vertices)
    me.vertices.foreach_set("co", m.V.astype(np.float32).ravel())
    me.loops.add(m.face_indices.size)
    me.loops.foreach_set("vertex_index", m.face_indices)
    me.polygons.add(m.n_faces)
    me.polygons.foreach_set("loop_start", m.face_offsets[:-1].astype(np.int32))
    if bpy.app.version < (4, 0, 0):
        me.polygons.foreach_set("loop_total", np.diff(m.face_offsets).astype(np.int32))
    me.update(calc_edges=True)
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    select(obj)
    return obj


def select(obj):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def result():
    """The last operator's result (``scene.meshmark.last_result``), printed as one JSON line (without
    the study's per-frame rows, which are in its CSV)."""
    r = json.loads(bpy.context.scene.meshmark.last_result)
    print("meshmark example:", json.dumps({k: v for k, v in r.items() if k != "rows"}, sort_keys=True))
    return r
