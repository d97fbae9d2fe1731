"""Geometry: triangulation, face normals and areas, angles, and PCA with a fixed axis sign.

Functions on triangles take a :class:`~meshmark.Mesh` or ``(V, F)``; polygon meshes are
triangulated first (see :func:`triangulate`). Angles are in radians, areas in squared model units.
"""
from __future__ import annotations

import numpy as np

from . import _core
from .mesh import as_mesh, FacesLike, MeshLike, _as_vertices
from typing import Any


def triangulate(V: MeshLike, F: FacesLike = None) -> tuple[np.ndarray, np.ndarray]:
    """Deterministic triangulation: ``(T (t, 3) int32, face (t,) int32 source polygon)``.

    Triangles are kept; other polygons are ear-clipped in the plane of their Newell normal, first
    ear first (the fan from corner 0 for convex polygons). See ``docs/mesh_model.md``.
    """
    m = as_mesh(V, F)
    return _core.triangulate(m.V, m.face_indices, m.face_offsets)


def _triangles(V, F):
    m = as_mesh(V, F)
    return m.V, np.ascontiguousarray(m.triangles)


def face_normals(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(t, 3) unit normals of the triangles (zero vector for zero-area triangles)."""
    return _core.face_normals(*_triangles(V, F))


def face_areas(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(t,) triangle areas."""
    return _core.face_areas(*_triangles(V, F))


def interior_angles(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(t, 3) interior angle at each triangle corner, radians."""
    return _core.interior_angles(*_triangles(V, F))


def dihedral_angles(V: MeshLike, F: FacesLike = None) -> tuple[np.ndarray, np.ndarray]:
    """Angle between the normals of the two triangles on each edge: ``(E (e, 2), angle (e,))``.

    0 for coplanar faces; NaN on boundary and non-manifold edges.
    """
    return _core.dihedral_angles(*_triangles(V, F))


def angle_sum(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(n,) sum of incident interior angles per vertex; ``2*pi - angle_sum`` is the angle deficit."""
    return _core.angle_sum(*_triangles(V, F))


def pca(V: MeshLike) -> dict:
    """Principal component analysis of points (a Mesh uses all its vertices).

    Returns a dict with ``centroid`` (3,), ``axes`` (3, 3) whose columns are q1, q2, q3,
    ``eigenvalues`` (3,) in descending order, and ``skewness`` (3,) the third central moment along
    each axis. Sign rule: each axis points to the side of positive skewness (longer tail), so the
    axes move with the mesh under rotation, translation, uniform scaling and reordering.
    """
    return _core.pca(_as_vertices(V))
