"""A summary of a mesh: counts, boundary, components, manifoldness, bounding box, edge length."""
from __future__ import annotations

from . import _core
from .mesh import as_mesh, FacesLike, MeshLike
from typing import Any


def mesh_info(V: MeshLike, F: FacesLike = None) -> dict:
    """Return a dict: n_vertices, n_faces, n_edges, n_boundary_edges, n_boundary_vertices,
    n_unreferenced_vertices, n_degenerate_faces, n_components, manifold, edge_manifold, closed,
    euler_characteristic, bbox_min, bbox_max, bbox_diagonal, mean_edge_length, surface_area,
    face_sizes ({corners: count}).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    Lengths in mesh units, ``surface_area`` in squared mesh units, ``bbox_min``/``bbox_max`` (3,)."""
    m = as_mesh(V, F)
    return _core.mesh_info(m.V, m.face_indices, m.face_offsets)
