"""Deformation attacks for studies, beside :data:`meshmark.attacks.ATTACKS` (which holds ``bend``,
the two-bone linear blend skinning bend, :func:`meshmark.attacks.bend`).

* ``blender_bend`` (only when ``bpy`` imports): Blender's Simple Deform modifier in Bend mode by
  ``degrees`` about ``axis`` (X, Y or Z), evaluated through the depsgraph, faces unchanged.
"""
from __future__ import annotations

import importlib.util
import math

import numpy as np

from .._core import MeshError
from ..mesh import Mesh, as_mesh


def blender_bend(V, F=None, *, degrees: float = 30.0, axis: str = "Z") -> Mesh:  # pragma: no cover - needs bpy
    import bpy

    m = as_mesh(V, F)
    if axis not in ("X", "Y", "Z"):
        raise MeshError(f"blender_bend axis must be X, Y or Z, got {axis!r}")
    me = bpy.data.meshes.new("meshmark-study")
    faces = np.split(m.face_indices, m.face_offsets[1:-1])
    me.from_pydata(m.V.tolist(), [], [f.tolist() for f in faces])
    ob = bpy.data.objects.new("meshmark-study", me)
    bpy.context.scene.collection.objects.link(ob)
    try:
        mod = ob.modifiers.new("bend", "SIMPLE_DEFORM")
        mod.deform_method, mod.deform_axis, mod.angle = "BEND", axis, math.radians(float(degrees))
        dg = bpy.context.evaluated_depsgraph_get()
        ev = ob.evaluated_get(dg).to_mesh()
        out = np.empty(len(ev.vertices) * 3)
        ev.vertices.foreach_get("co", out)
        ob.evaluated_get(dg).to_mesh_clear()
    finally:
        bpy.data.objects.remove(ob)
        bpy.data.meshes.remove(me)
    return Mesh.from_polygons(out.reshape(-1, 3), m.face_indices, m.face_offsets, validate=False)


DEFORMATIONS: dict = {}
if importlib.util.find_spec("bpy") is not None:  # pragma: no cover - needs bpy
    DEFORMATIONS["blender_bend"] = (blender_bend, {"degrees", "axis"})


def available() -> dict:
    """name -> accepted parameter names."""
    return {k: set(v[1]) for k, v in DEFORMATIONS.items()}


def apply(name: str, mesh, params: dict, seed: int = 0) -> Mesh:
    fn, _ = DEFORMATIONS[name]
    return fn(mesh, **params)
