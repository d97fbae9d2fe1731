"""Topology of the edge graph: edges, adjacency, boundary, components, manifoldness.

Every function takes a :class:`~meshmark.Mesh` or ``(V, F)``; polygons count with their sides as
stored (a quad has 4 edges, no diagonal). All loops run natively.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _core
from ._core import MeshError
from .mesh import as_mesh, FacesLike, Mesh, MeshLike
from ._typing import ArrayLike
from typing import Any


def unique_edges(V: MeshLike, F: FacesLike = None) -> tuple[np.ndarray, np.ndarray]:
    """Unique undirected edges.

    Returns ``E`` (e, 2) int32 with ``E[:, 0] < E[:, 1]``, sorted lexicographically, and
    ``face_count`` (e,) int32: the number of face sides on each edge (1 boundary, 2 interior,
    > 2 non-manifold).
    """
    m = as_mesh(V, F)
    return _core.unique_edges(m.n_vertices, m.face_indices, m.face_offsets)


def vertex_adjacency(V: MeshLike, F: FacesLike = None) -> tuple[np.ndarray, np.ndarray]:
    """CSR adjacency: ``(ptr (n+1,) int64, nbr (2e,) int32)``; neighbours of i are ``nbr[ptr[i]:ptr[i+1]]``, sorted."""
    m = as_mesh(V, F)
    E, _ = unique_edges(m)
    return _core.vertex_adjacency(m.n_vertices, E)


def valence(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(n,) int32 number of distinct neighbours of each vertex (0 if unreferenced)."""
    m = as_mesh(V, F)
    return _core.valence(m.n_vertices, unique_edges(m)[0])


def boundary_edges(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(b, 2) int32 edges that lie on exactly one face."""
    E, count = unique_edges(V, F)
    return E[count == 1]


def boundary_vertices(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """Sorted (k,) int32 indices of vertices on a boundary edge."""
    m = as_mesh(V, F)
    E, count = unique_edges(m)
    return _core.boundary_vertices(m.n_vertices, E, count)


def connected_components(V: MeshLike, F: FacesLike = None) -> tuple[np.ndarray, int]:
    """Components of the edge graph: ``(labels (n,) int32, count)``.

    Labels are numbered in order of each component's lowest vertex index; unreferenced vertices
    get -1 and are not counted.
    """
    m = as_mesh(V, F)
    return _core.connected_components(m.n_vertices, unique_edges(m)[0])


def manifold_report(V: MeshLike, F: FacesLike = None) -> dict:
    """Counts of non-manifold edges (> 2 faces) and vertices (faces not forming one fan).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    m = as_mesh(V, F)
    return _core.manifold_report(m.n_vertices, m.face_indices, m.face_offsets)


@dataclass(frozen=True)
class Welded:
    """The result of :func:`weld_vertices`.

    ``mesh``: the welded mesh (k vertices; the input Mesh object itself when nothing merges);
    ``map``: (n,) int32, the welded vertex of each input vertex; ``first``: (k,) int32, the first input
    vertex of each welded vertex (increasing: welded vertices keep the order of first occurrence);
    ``face``: (m',) int32, the input face of each kept face.
    """
    mesh: Mesh
    map: np.ndarray
    first: np.ndarray
    face: np.ndarray

    @property
    def n_merged(self) -> int:
        """How many input vertices were merged into an earlier copy (n - k)."""
        return int(self.map.shape[0] - self.first.shape[0])

    def scatter(self, V: ArrayLike) -> np.ndarray:
        """(n, 3) positions of the input vertices from (k, 3) positions of the welded ones: every
        copy of a welded vertex gets exactly the same coordinates."""
        V = np.asarray(V)
        if V.shape[0] != self.first.shape[0]:
            raise ValueError(f"expected {self.first.shape[0]} welded positions, got {V.shape[0]}")
        return V if self.n_merged == 0 else V[self.map]


def weld_vertices(V: MeshLike, F: FacesLike = None) -> Welded:
    """Merge vertices whose coordinates are exactly equal (as float64; ``-0.0 == 0.0``).

    Exporters split a vertex into coincident copies at UV seams and sharp edges, and non-indexed
    glTF or STL files store every triangle corner separately; the edge graph of such a mesh falls
    apart into pieces. Welding gives back the connected mesh: faces are reindexed, a corner that
    repeats the previous one is removed, and a face left with fewer than 3 corners (or still
    repeating a vertex) is dropped. Exact equality, no tolerance: see ``docs/mesh_model.md``.
    One native hash pass, O(n + corners).

    Returns a :class:`Welded` (``mesh``, ``map``, ``first``, ``face``, ``scatter``).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    m = as_mesh(V, F)
    first, vmap, idx, off, face = _core.weld_vertices(m.V, m.face_indices, m.face_offsets)
    if first.shape[0] == m.n_vertices:  # nothing merges: the native side leaves the faces alone
        return Welded(mesh=m, map=vmap, first=first, face=np.arange(m.n_faces, dtype=np.int32))
    if face.shape[0] == 0:
        raise MeshError(f"welding the {m.n_vertices} vertices at equal positions leaves no face: every face collapses")
    return Welded(mesh=Mesh.from_polygons(m.V[first], idx, off, validate=False), map=vmap, first=first, face=face)
