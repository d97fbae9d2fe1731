"""Helpers shared by the bench scripts (timing, subdivided shared meshes). Not a test module."""
from __future__ import annotations

import pathlib
import time

import numpy as np

import meshmark

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes"


def best_of(fn, repeat: int = 5):
    """Best wall time (s) over `repeat` runs, and the last result."""
    best, out = float("inf"), None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def midpoint_subdivide(V: np.ndarray, F: np.ndarray):
    """One level of 1-to-4 midpoint subdivision (vectorized numpy)."""
    E, _ = meshmark.unique_edges(V, F)
    n = len(V)
    key = lambda a, b: np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b)
    ekey = E[:, 0].astype(np.int64) * n + E[:, 1]
    mid = lambda a, b: n + np.searchsorted(ekey, key(a, b))
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
    F2 = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1), np.stack([c, ca, bc], 1),
                         np.stack([ab, bc, ca], 1)])
    V2 = np.vstack([V, 0.5 * (V[E[:, 0]] + V[E[:, 1]])])
    return V2, F2.astype(np.int32)


def big_bunny(min_faces: int = 1_000_000) -> meshmark.Mesh:
    """The shared Stanford bunny, midpoint-subdivided until it has at least `min_faces` triangles."""
    m = meshmark.read_mesh(SHARED / "classic" / "bunny.obj")
    V, F = m.V, m.F
    while len(F) < min_faces:
        V, F = midpoint_subdivide(V, F)
    return meshmark.Mesh(V, F)
