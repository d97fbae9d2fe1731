"""meshmark.stego float32 path through Blender (issue 13): the marked float32 words are written with
``foreach_set("co")``, the .blend is saved and reopened, read back with ``foreach_get`` and the message
comes back exactly, on every shared classic mesh at 1 deg."""
import os

import bpy
import numpy as np
import pytest

import meshmark
from meshmark import stego
from blender_tests import rigs
from blender_tests.conftest import mesh_arrays

CLASSIC = ["bunny.obj", "horse.ply", "elephant.off", "fandisk.obj", "cow.obj", "spot.obj", "suzanne.obj",
           "hand.obj", "fertility.off", "teapot.obj", "camelhead.off", "homer.obj"]


def blender_object(name, mesh, V):
    """A mesh object from arrays via foreach_set, without me.validate() (which may drop faces)."""
    me = bpy.data.meshes.new(name)
    me.vertices.add(mesh.n_vertices)
    me.vertices.foreach_set("co", V.astype(np.float32).ravel())
    me.loops.add(mesh.face_indices.size)
    me.loops.foreach_set("vertex_index", mesh.face_indices)
    me.polygons.add(mesh.n_faces)
    me.polygons.foreach_set("loop_start", mesh.face_offsets[:-1].astype(np.int32))
    me.update(calc_edges=True)
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    return obj


@pytest.mark.parametrize("name", CLASSIC)
def test_float32_through_blender(name, tmp_path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    mesh = meshmark.read_mesh(rigs.shared_mesh(f"classic/{name}"))
    payload = os.urandom(min(1500, stego.capacity(mesh, tolerance=1.0, precision="float32")["max_message_bytes"]))
    res = stego.embed(mesh, payload, "blender key", tolerance=1.0, precision="float32")
    assert np.array_equal(res.V.astype(np.float32).astype(np.float64), res.V)  # float32 words
    blender_object("marked", mesh, res.V)
    path = str(tmp_path / "m.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    V, loops, offsets = mesh_arrays(bpy.data.objects["marked"])
    assert np.array_equal(V, res.V)
    back = meshmark.Mesh.from_polygons(V, loops, offsets)
    got = stego.extract(back, "blender key", tolerance=1.0, precision="float32")
    assert got.found and got.message == payload
    assert not stego.extract(back, "other key", tolerance=1.0, precision="float32").found
