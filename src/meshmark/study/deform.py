"""Deformation attacks for studies, beside :data:`meshmark.attacks.ATTACKS`.

* ``bend``: two-bone linear blend skinning about the x axis (numpy, vectorised): vertices below
  ``joint - width`` (along z) stay, those above ``joint + width`` rotate by ``degrees`` about the
  joint, smoothstep weights between. ``joint`` and ``width`` are fractions of the z extent of the
  mesh (default 0.5 and 0.1), or absolute z values with ``absolute = true`` (the arm of
  ``tests/test_laplacian_watermark.py`` bends at z = 1 with width 0.2). Deterministic, no seed.
* ``blender_bend`` (only when ``bpy`` imports): Blender's Simple Deform modifier in Bend mode by
  ``degrees`` about ``axis`` (X, Y or Z), evaluated through the depsgraph, faces unchanged.
"""
from __future__ import annotations

import importlib.util
import math

import numpy as np

from .._core import MeshError
from ..mesh import Mesh, as_mesh


def bend(V, F=None, *, degrees: float = 30.0, joint: float = 0.5, width: float = 0.1, absolute: bool = False) -> Mesh:
    m = as_mesh(V, F)
    deg = float(degrees)
    if not math.isfinite(deg):
        raise MeshError(f"bend degrees must be finite, got {degrees!r}")
    X = m.V
    if absolute:
        j, w = float(joint), float(width)
    else:
        lo, hi = float(X[:, 2].min()), float(X[:, 2].max())
        j, w = lo + float(joint) * (hi - lo), float(width) * (hi - lo)
    if not w > 0:
        raise MeshError(f"bend width must be > 0, got {width!r}")
    t = np.clip((X[:, 2] - (j - w)) / (2 * w), 0, 1)
    s = t * t * (3 - 2 * t)
    a = np.radians(deg)
    R = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    c = np.array([0, 0, j])
    V2 = (1 - s)[:, None] * X + s[:, None] * ((X - c) @ R.T + c)
    return Mesh.from_polygons(V2, m.face_indices, m.face_offsets, validate=False)


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


DEFORMATIONS = {"bend": (bend, {"degrees", "joint", "width", "absolute"})}
if importlib.util.find_spec("bpy") is not None:  # pragma: no cover - needs bpy
    DEFORMATIONS["blender_bend"] = (blender_bend, {"degrees", "axis"})


def available() -> dict:
    """name -> accepted parameter names."""
    return {k: set(v[1]) for k, v in DEFORMATIONS.items()}


def apply(name: str, mesh, params: dict, seed: int = 0) -> Mesh:
    fn, _ = DEFORMATIONS[name]
    return fn(mesh, **params)
