"""Helpers of the ch. 6 example scripts: shared meshes, the simple attacks of §6.3 in numpy, metrics.

The attacks are implemented here on purpose (a few lines of numpy each) so that the examples do not
depend on the attacks module being built elsewhere.
"""
from __future__ import annotations

import pathlib

import numpy as np
import scipy.sparse as sp

import meshmark
from meshmark.metrics import correlation as _correlation

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "meshes"


def load(rel: str):
    """(mesh, referenced-vertex mesh as (V, F) with unreferenced vertices dropped)."""
    m = meshmark.read_mesh(SHARED / rel)
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    remap = np.cumsum(used) - 1
    T = remap[m.triangles]
    return m.V[used], T.astype(np.int32)


def diag(V) -> float:
    return float(np.linalg.norm(V.max(0) - V.min(0)))


def noise(V, A_percent: float, rng) -> np.ndarray:
    """Eq. 6.3.12: x' = x + a * d_mean, a ~ U[-A, A] independently per coordinate, d_mean the mean
    distance of the vertices from their centroid."""
    d = float(np.linalg.norm(V - V.mean(0), axis=1).mean())
    return V + rng.uniform(-A_percent / 100, A_percent / 100, V.shape) * d


def smooth(V, F, lam: float, iterations: int) -> np.ndarray:
    """Laplacian (umbrella) smoothing: v <- v + lambda (mean of the neighbours - v), repeated."""
    n = len(V)
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n)).tocsr()
    A = ((A + A.T) > 0).astype(float)
    deg = np.asarray(A.sum(1)).ravel()
    W = sp.diags(1.0 / np.maximum(deg, 1)) @ A
    X = V.copy()
    for _ in range(iterations):
        X = X + lam * (W @ X - X)
    return X


def quantize(V, bits: int) -> np.ndarray:
    """Uniform quantisation of every coordinate to 2^bits levels over the bounding box's largest side."""
    lo = V.min(0)
    step = float((V.max(0) - lo).max()) / (2 ** bits - 1)
    return lo + np.round((V - lo) / step) * step


def correlation(w, w2) -> float:
    return _correlation(np.asarray(w), np.asarray(w2))


def cdr(w, w2) -> float:
    return float(np.mean(np.asarray(w) == np.asarray(w2)))
