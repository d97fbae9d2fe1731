"""Topology of the edge graph: edges, adjacency, boundary, components, manifoldness.

Every function takes a :class:`~meshmark.Mesh` or ``(V, F)``; polygons count with their sides as
stored (a quad has 4 edges, no diagonal). All loops run natively.
"""
from __future__ import annotations

import numpy as np

from . import _core
from .mesh import as_mesh


def unique_edges(V, F=None) -> tuple[np.ndarray, np.ndarray]:
    """Unique undirected edges.

    Returns ``E`` (e, 2) int32 with ``E[:, 0] < E[:, 1]``, sorted lexicographically, and
    ``face_count`` (e,) int32: the number of face sides on each edge (1 boundary, 2 interior,
    > 2 non-manifold).
    """
    m = as_mesh(V, F)
    return _core.unique_edges(m.n_vertices, m.face_indices, m.face_offsets)


def vertex_adjacency(V, F=None) -> tuple[np.ndarray, np.ndarray]:
    """CSR adjacency: ``(ptr (n+1,) int64, nbr (2e,) int32)``; neighbours of i are ``nbr[ptr[i]:ptr[i+1]]``, sorted."""
    m = as_mesh(V, F)
    E, _ = unique_edges(m)
    return _core.vertex_adjacency(m.n_vertices, E)


def valence(V, F=None) -> np.ndarray:
    """(n,) int32 number of distinct neighbours of each vertex (0 if unreferenced)."""
    m = as_mesh(V, F)
    return _core.valence(m.n_vertices, unique_edges(m)[0])


def boundary_edges(V, F=None) -> np.ndarray:
    """(b, 2) int32 edges that lie on exactly one face."""
    E, count = unique_edges(V, F)
    return E[count == 1]


def boundary_vertices(V, F=None) -> np.ndarray:
    """Sorted (k,) int32 indices of vertices on a boundary edge."""
    m = as_mesh(V, F)
    E, count = unique_edges(m)
    return _core.boundary_vertices(m.n_vertices, E, count)


def connected_components(V, F=None) -> tuple[np.ndarray, int]:
    """Components of the edge graph: ``(labels (n,) int32, count)``.

    Labels are numbered in order of each component's lowest vertex index; unreferenced vertices
    get -1 and are not counted.
    """
    m = as_mesh(V, F)
    return _core.connected_components(m.n_vertices, unique_edges(m)[0])


def manifold_report(V, F=None) -> dict:
    """Counts of non-manifold edges (> 2 faces) and vertices (faces not forming one fan)."""
    m = as_mesh(V, F)
    return _core.manifold_report(m.n_vertices, m.face_indices, m.face_offsets)
