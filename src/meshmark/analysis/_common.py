"""Input handling shared by the analysis modules."""
from __future__ import annotations

import math

import numpy as np

from .._core import MeshError
from ..mesh import Mesh, as_mesh


def mesh_arrays(mesh, name: str = "mesh"):
    """(Mesh, V (n, 3) float64, T (t, 3) int32) from a Mesh or a (V, F) tuple; polygons are
    triangulated deterministically (Mesh.triangles). MeshError for anything else or no face."""
    if isinstance(mesh, Mesh):
        m = mesh
    elif isinstance(mesh, tuple) and len(mesh) == 2:
        m = as_mesh(*mesh)
    else:
        raise MeshError(f"{name} must be a meshmark.Mesh or a (V, F) tuple, got {type(mesh).__name__}")
    # whether every face is a triangle is a property of the face set: remembered with it (with_vertices
    # shares it), so that repeated levels on new positions (meshmark.stego) skip the check
    tri = m._topology.get("all_triangles")
    if tri is None:
        tri = m._topology["all_triangles"] = m.is_triangle_mesh
    T = m.face_indices.reshape(-1, 3) if tri else m.triangles
    T = np.ascontiguousarray(T, dtype=np.int32)
    if len(T) == 0:
        raise MeshError(f"{name} has no triangle")
    return m, m.V, T


def positive(x, name: str) -> float:
    """A finite number > 0 (MeshError naming the parameter otherwise)."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise MeshError(f"{name} must be a number, got {x!r}") from None
    if not (v > 0 and math.isfinite(v)):
        raise MeshError(f"{name} must be a finite number > 0, got {x!r}")
    return v


def seed_value(seed) -> int:
    """An integer seed in 0 .. 2^64 - 1 (the attacks' rule)."""
    from ..attacks import _seed
    return _seed(seed)
