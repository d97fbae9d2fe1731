"""Blender mesh data <-> numpy and meshmark.Mesh, with foreach_get/foreach_set only (no
per-vertex Python). Coordinates are in object space, as Blender stores them (float32).

Also here: :func:`cage_only` (read a posed mesh through its deforming modifiers only, so that a live
Subdivision does not change the vertices a mark was put in) and :func:`steganalysis_verdict` (the
three states the panel shows for a steganalysis result).
"""
from __future__ import annotations

import contextlib

import bpy
import numpy as np

import meshmark


class BlenderInputError(meshmark.MeshError):
    """Something about the Blender side (no object, wrong type, edit mode) that stops an operator."""


def active_mesh_object(context):
    obj = getattr(context, "active_object", None) or getattr(context.view_layer.objects, "active", None)
    if obj is None:
        raise BlenderInputError("no active object: select a mesh object first")
    if obj.type != "MESH":
        raise BlenderInputError(f"the active object '{obj.name}' is a {obj.type.lower()}, not a mesh")
    if obj.mode == "EDIT":
        raise BlenderInputError(f"'{obj.name}' is in Edit Mode: switch to Object Mode first")
    return obj


def _coords(collection, n: int) -> np.ndarray:
    co = np.empty(3 * n, np.float32)
    collection.foreach_get("co", co)
    return co.reshape(n, 3)


def _loop_vertices(me, c: int) -> np.ndarray:
    """(c,) int32 vertex of every loop. Blender 4+ stores them as the ``.corner_vert`` attribute,
    whose foreach_get copies the array (0.3 ms for 800k loops); ``loops.vertex_index`` goes through RNA
    per loop (0.1-0.15 s)."""
    loops = np.empty(c, np.int32)
    attr = me.attributes.get(".corner_vert") if bpy.app.version >= (4, 0, 0) else None
    if attr is not None and attr.domain == "CORNER" and attr.data_type == "INT" and len(attr.data) == c:
        attr.data.foreach_get("value", loops)
    else:
        me.loops.foreach_get("vertex_index", loops)
    return loops


def faces(me):
    """(loop vertex indices int32, offsets int64) of a Blender mesh (polygons as stored)."""
    m, c = len(me.polygons), len(me.loops)
    loops = _loop_vertices(me, c)
    starts = np.empty(m, np.int32)
    me.polygons.foreach_get("loop_start", starts)
    offsets = np.zeros(m + 1, np.int64)
    if bpy.app.version >= (4, 0, 0):  # polygons are offsets into the loops, in order (4.0+)
        offsets[:-1], offsets[-1] = starts, c
        return loops, offsets
    totals = np.empty(m, np.int32)
    me.polygons.foreach_get("loop_total", totals)
    np.cumsum(totals, out=offsets[1:])
    if m and not (starts == offsets[:-1]).all():  # Blender keeps loops in polygon order; be safe
        order = np.argsort(starts, kind="stable")
        loops = np.concatenate([loops[s:s + t] for s, t in zip(starts[order], totals[order])])
        offsets[1:] = np.cumsum(totals[order])
    return loops, offsets


def base_coords(me) -> np.ndarray:
    """(n, 3) float32 base positions: the reference (Basis) shape key if any, else vertices."""
    n = len(me.vertices)
    if me.shape_keys is not None and me.shape_keys.reference_key is not None:
        return _coords(me.shape_keys.reference_key.data, n)
    return _coords(me.vertices, n)


def base_mesh(obj) -> meshmark.Mesh:
    """The undeformed mesh of ``obj`` (its Basis), no modifiers, as a validated meshmark.Mesh."""
    me = obj.data
    loops, offsets = faces(me)
    return meshmark.Mesh.from_polygons(base_coords(me).astype(np.float64), loops, offsets)


# Modifiers that only move vertices (or set attributes, normals, UVs, weights): the evaluated mesh
# keeps the base mesh's vertices, in order. Every other modifier (Subdivision, Mirror, Triangulate,
# Geometry Nodes, ...) may add, remove or reconnect vertices.
DEFORMING = frozenset({
    "ARMATURE", "CAST", "CURVE", "DISPLACE", "HOOK", "LAPLACIANDEFORM", "LATTICE", "MESH_DEFORM", "SHRINKWRAP",
    "SIMPLE_DEFORM", "SMOOTH", "CORRECTIVE_SMOOTH", "LAPLACIANSMOOTH", "SURFACE_DEFORM", "WARP", "WAVE",
    "MESH_CACHE", "MESH_SEQUENCE_CACHE", "CLOTH", "SOFT_BODY", "COLLISION", "DYNAMIC_PAINT", "SURFACE",
    "PARTICLE_SYSTEM", "DATA_TRANSFER", "NORMAL_EDIT", "WEIGHTED_NORMAL", "UV_PROJECT", "UV_WARP",
    "VERTEX_WEIGHT_EDIT", "VERTEX_WEIGHT_MIX", "VERTEX_WEIGHT_PROXIMITY"})


def reshaping_modifiers(obj) -> list:
    """The modifiers of ``obj`` shown in the viewport that may change its vertices (not in :data:`DEFORMING`)."""
    return [m for m in getattr(obj, "modifiers", ()) if m.show_viewport and m.type not in DEFORMING]


@contextlib.contextmanager
def cage_only(objects):
    """Evaluate ``objects`` through their deforming modifiers only: modifiers that change the vertices
    (:func:`reshaping_modifiers`) are switched off in the viewport for the ``with`` block and switched
    back on after it, whatever happens. Yields the list of ``(object name, modifier name)`` left out.

    The mark lives in the base mesh (the cage of a Subdivision); the armature, shape keys and lattices
    move those vertices, and that posed cage is what verification reads."""
    off = []
    try:
        for o in objects:
            for m in reshaping_modifiers(o):
                try:
                    m.show_viewport = False
                except (AttributeError, RuntimeError):  # a linked (library) object: leave it
                    continue
                off.append((o, m))
        yield [(o.name, m.name) for o, m in off]
    finally:
        for o, m in off:
            try:
                m.show_viewport = True
            except ReferenceError:  # pragma: no cover - deleted meanwhile
                pass


def evaluated_mesh(context, obj) -> meshmark.Mesh:
    """The mesh as the depsgraph evaluates it now (armature, shape keys, lattice, other modifiers);
    within :func:`cage_only`, through the deforming modifiers only."""
    dg = context.evaluated_depsgraph_get()
    ob_eval = obj.evaluated_get(dg)
    me = ob_eval.to_mesh()
    try:
        loops, offsets = faces(me)
        V = _coords(me.vertices, len(me.vertices)).astype(np.float64)
    finally:
        ob_eval.to_mesh_clear()
    return meshmark.Mesh.from_polygons(V, loops, offsets)


def apply_displacement(obj, D: np.ndarray) -> None:
    """Add the (n, 3) displacement ``D`` to the base mesh and to every shape key, so that the Basis
    takes the mark and every key keeps its offset from the Basis. UVs, vertex groups, attributes and
    topology are untouched (only positions are written)."""
    me = obj.data
    n = len(me.vertices)
    D = np.asarray(D, np.float64)
    if D.shape != (n, 3):
        raise ValueError(f"displacement has shape {D.shape}, the mesh has {n} vertices")
    targets = [me.vertices]
    if me.shape_keys is not None:
        targets += [kb.data for kb in me.shape_keys.key_blocks]
    for coll in targets:
        co = _coords(coll, n).astype(np.float64)
        coll.foreach_set("co", (co + D).astype(np.float32).ravel())
    me.update()
    obj.update_tag()


def bbox_diagonal(V: np.ndarray) -> float:
    return float(np.linalg.norm(V.max(0) - V.min(0))) if len(V) else 0.0


def coordinate_targets(me) -> list:
    """Every coordinate array of a mesh: the vertices, then each shape key's (in order)."""
    return [me.vertices] + ([kb.data for kb in me.shape_keys.key_blocks] if me.shape_keys is not None else [])


def snapshot_coords(me) -> list:
    """Copies (float32) of every coordinate array of ``me``, for :func:`restore_coords`."""
    n = len(me.vertices)
    return [_coords(c, n).copy() for c in coordinate_targets(me)]


def restore_coords(obj, saved: list) -> None:
    """Put back what :func:`snapshot_coords` took: the mesh is bit-identical afterwards."""
    me = obj.data
    for coll, co in zip(coordinate_targets(me), saved):
        coll.foreach_set("co", co.ravel())
    me.update()
    obj.update_tag()


def write_base_exact(obj, V32: np.ndarray) -> None:
    """Set the base mesh to the float32 positions ``V32`` exactly (the vertices and the Basis key);
    other shape keys keep their offset from the Basis (rounded to float32)."""
    me = obj.data
    n = len(me.vertices)
    V32 = np.ascontiguousarray(V32, np.float32).reshape(n, 3)
    ref = me.shape_keys.reference_key if me.shape_keys is not None else None
    old = base_coords(me).astype(np.float64)
    if me.shape_keys is not None:
        for kb in me.shape_keys.key_blocks:
            if kb != ref:
                co = _coords(kb.data, n).astype(np.float64)
                kb.data.foreach_set("co", (co - old + V32).astype(np.float32).ravel())
        ref.data.foreach_set("co", V32.ravel())
    me.vertices.foreach_set("co", V32.ravel())
    me.update()
    obj.update_tag()


# -- steganalysis: the panel's three states ------------------------------------------------------------
# Smallest mesh the built-in detector learned from: its training covers start at an icosphere of two
# midpoint subdivisions (162 vertices, meshmark.steganalysis.generated); below that its features say
# nothing about the mesh.
STEGANALYSIS_MIN_VERTICES = 162
VERDICTS = ("marked", "clean", "cannot_judge")


def steganalysis_verdict(result: dict, n_vertices: int) -> dict:
    """Adapter from ``Model.detect``'s result to the panel's three states: ``{"state": "marked" | "clean"
    | "cannot_judge", "why": "too_small" | "out_of_range" | ""}``.

    Today's core says ``marked`` and, for a model with a guard, ``in_distribution``; "cannot judge" is
    derived here (too few vertices, or features outside the model's training range). When the core
    reports the outcome itself, read it here first (the one place to wire it)."""
    if n_vertices < STEGANALYSIS_MIN_VERTICES:
        return {"state": "cannot_judge", "why": "too_small"}
    if result.get("in_distribution") is False:
        return {"state": "cannot_judge", "why": "out_of_range"}
    return {"state": "marked" if result.get("marked") else "clean", "why": ""}
