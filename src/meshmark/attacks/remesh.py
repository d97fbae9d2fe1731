"""Isotropic remeshing (CGAL's ``Polygon_mesh_processing::isotropic_remeshing``), native."""
from __future__ import annotations

from .. import _core
from .._core import MeshError
from ..mesh import as_mesh, FacesLike, Mesh, MeshLike
from .basic import _finite, _tri


def remesh(V: MeshLike, F: FacesLike = None, *, edge_length: float = 1.0, iterations: int = 3,
           return_target: bool = False) -> Mesh | tuple[Mesh, float]:
    """Isotropic remeshing towards edges of ``edge_length`` x the mean edge length of the input.

    CGAL's ``isotropic_remeshing`` (Botsch and Kobbelt 2004): ``iterations`` rounds (default 3) of
    splitting edges longer than 4/3 L, collapsing edges shorter than 4/5 L, flipping edges towards
    valence 6 and tangential relaxation, with the vertices projected back onto the input surface.
    L = ``edge_length`` (a multiple, default 1: the mean length of the unique edges of the referenced
    triangles; 0.5 halves the edges, about 4x the triangles). Borders are remeshed too, their vertices
    stay on the border. Polygons are triangulated first; unreferenced vertices are dropped; the
    result is triangles in CGAL's vertex order. Deterministic (no seed).

    MeshError when the triangles are not a manifold surface (an edge shared by more than two
    triangles, a pinched vertex), when a triangle has zero area, when ``edge_length`` is not in
    (0, 100] or ``iterations`` not in 1..100, or when the target would make more than 2e7 triangles.
    With ``return_target`` returns ``(mesh, L in model units)``.
    """
    m = as_mesh(V, F)
    rel = _finite(edge_length, "remesh edge length")
    if isinstance(iterations, bool) or int(iterations) != iterations:
        raise MeshError(f"remesh iterations must be an integer in 1..100, got {iterations!r}")
    if m.n_faces == 0:
        raise MeshError("remesh: the mesh has no faces")
    V2, T2, L = _core.remesh(m.V, _tri(m), rel, int(iterations))
    out = Mesh(V2, T2)
    return (out, float(L)) if return_target else out
