"""Blender smoke test: a mesh built in Blender, read with foreach_get into meshmark; counts agree."""
import bmesh
import bpy
import numpy as np

import meshmark
from blender_tests.conftest import mesh_arrays


def _blender_counts(obj):
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    boundary = sum(1 for e in bm.edges if e.is_boundary)
    non_manifold = sum(1 for e in bm.edges if len(e.link_faces) > 2)
    bm.free()
    me = obj.data
    return len(me.vertices), len(me.polygons), len(me.edges), boundary, non_manifold


def test_blender_version_is_supported():
    assert bpy.app.version >= (4, 2, 0), bpy.app.version_string


def test_monkey_counts_match(empty_scene):
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    V, loops, offsets = mesh_arrays(obj)
    m = meshmark.Mesh.from_polygons(V, loops, offsets)
    d = meshmark.mesh_info(m)
    nv, nf, ne, nb, nnm = _blender_counts(obj)
    assert (d["n_vertices"], d["n_faces"], d["n_edges"]) == (nv, nf, ne) == (507, 500, 1005)
    assert d["n_boundary_edges"] == nb == 42
    assert d["non_manifold_edges"] == nnm == 0
    assert d["face_sizes"] == {"3": 32, "4": 468}
    assert d["n_components"] == 3  # head and two eyes


def test_subdivided_quads_and_ngons(empty_scene):
    bpy.ops.mesh.primitive_cylinder_add(vertices=24, end_fill_type="NGON")  # two 24-gon caps
    obj = bpy.context.active_object
    mod = obj.modifiers.new("sub", "SUBSURF")
    mod.levels = 2
    V, loops, offsets = mesh_arrays(obj)
    m = meshmark.Mesh.from_polygons(V, loops, offsets)
    d = meshmark.mesh_info(m)
    nv, nf, ne, nb, _ = _blender_counts(obj)
    assert (d["n_vertices"], d["n_faces"], d["n_edges"]) == (nv, nf, ne) == (48, 26, 72)
    assert d["face_sizes"] == {"4": 24, "24": 2} and d["closed"] and nb == 0
    # the evaluated mesh (modifier applied) is all quads, closed and manifold
    Ve, le, oe = mesh_arrays(obj, evaluated=True)
    de = meshmark.mesh_info(meshmark.Mesh.from_polygons(Ve, le, oe))
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    assert (de["n_vertices"], de["n_faces"], de["n_edges"]) == (len(ev.vertices), len(ev.polygons), len(ev.edges))
    assert de["face_sizes"] == {"4": de["n_faces"]} and de["closed"] and de["manifold"]
    # triangulation agrees with Blender's loop triangles on the base mesh
    obj.data.calc_loop_triangles()
    assert len(meshmark.triangulate(m)[0]) == len(obj.data.loop_triangles) == 24 * 2 + 2 * 22
    assert len(m.triangles) == sum(k - 2 for k in m.face_sizes)
