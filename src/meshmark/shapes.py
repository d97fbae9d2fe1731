"""Built-in procedural meshes: the default inputs of demos and tests (no files needed).

All return a :class:`~meshmark.Mesh` with float64 vertices; construction is vectorized numpy.
"""
from __future__ import annotations

import numpy as np

from .mesh import Mesh


def _grid_quads(rows: int, cols: int, wrap_cols: bool, wrap_rows: bool) -> np.ndarray:
    """Quad faces of a rows x cols vertex grid (vertex id = r * cols + c)."""
    r = np.arange(rows if wrap_rows else rows - 1)
    c = np.arange(cols if wrap_cols else cols - 1)
    R, C = np.meshgrid(r, c, indexing="ij")
    R1, C1 = (R + 1) % rows, (C + 1) % cols
    return np.stack([R * cols + C, R * cols + C1, R1 * cols + C1, R1 * cols + C], axis=-1).reshape(-1, 4)


def torus(major_segments: int = 96, minor_segments: int = 48, major_radius: float = 1.0,
          minor_radius: float = 0.35, quads: bool = False) -> Mesh:
    """Closed genus-1 torus around the z axis; triangles unless ``quads``."""
    u = np.linspace(0, 2 * np.pi, major_segments, endpoint=False)
    v = np.linspace(0, 2 * np.pi, minor_segments, endpoint=False)
    U, Vv = np.meshgrid(u, v, indexing="ij")
    ring = major_radius + minor_radius * np.cos(Vv)
    V = np.stack([ring * np.cos(U), ring * np.sin(U), minor_radius * np.sin(Vv)], -1).reshape(-1, 3)
    Q = _grid_quads(major_segments, minor_segments, True, True)
    return Mesh(V, Q if quads else _split_quads(Q))


def cylinder(segments: int = 64, rings: int = 128, radius: float = 0.15, length: float = 2.0,
             capped: bool = True) -> Mesh:
    """A tube along +z from z=0 to z=length (an "arm"), optionally closed by fan caps."""
    u = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    z = np.linspace(0, length, rings)
    Z, U = np.meshgrid(z, u, indexing="ij")
    V = np.stack([radius * np.cos(U), radius * np.sin(U), Z], -1).reshape(-1, 3)
    F = _split_quads(_grid_quads(rings, segments, True, False))
    if capped:
        n = V.shape[0]
        V = np.vstack([V, [[0, 0, 0], [0, 0, length]]])
        c = np.arange(segments)
        bottom = np.stack([np.full(segments, n), (c + 1) % segments, c], -1)
        top_ring = (rings - 1) * segments
        top = np.stack([np.full(segments, n + 1), top_ring + c, top_ring + (c + 1) % segments], -1)
        F = np.vstack([F, bottom, top])
    return Mesh(V, F)


def _split_quads(Q: np.ndarray) -> np.ndarray:
    return np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])


def default_mesh() -> Mesh:
    """The built-in default: a torus with a smooth bumpy surface (9,216 triangles)."""
    m = torus()
    V = m.V.copy()
    theta = np.arctan2(V[:, 1], V[:, 0])
    V *= (1.0 + 0.05 * np.sin(5 * theta))[:, None]
    return Mesh(V, m.F)
