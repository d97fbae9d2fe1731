"""Generated meshes for the default steganalysis model (docs/steganalysis.md, "Default model on unseen
meshes"): covers that are NOT in ../shared, in two disjoint groups of families.

* :func:`holdout_covers` — the **hold-out** families, never used for training or for choosing the
  operating point: ``torus-tube`` (the study's procedural tori and capped tubes with bumps and jitter:
  regular grids, valence 6), ``superquadric`` (latitude-longitude grids with two pole fans, random
  exponents and axes), ``hull-blob`` (star-shaped blobs over the convex hull of random points on the
  sphere: irregular Delaunay-like triangulations). A fourth hold-out family, Blender primitives
  (Suzanne, UV sphere, cone, cylinder, cube) with subdivision / displace / remesh / decimate modifiers,
  is made by ``examples/steganalysis_blender_holdout.py`` in a separate process (bpy).
* :func:`training_covers` — **training-only** families: ``icosphere`` (midpoint-subdivided icosahedra
  pushed to ellipsoids, valence 6 with twelve 5s), ``loop-solid`` (Loop-subdivided cubes, octahedra and
  tetrahedra with bumps), ``heightfield`` (open terrain grids with random diagonals: a boundary).
* :func:`open_variants` — training-only re-meshings of a cover: edge-collapse simplification, additive
  noise, midpoint subdivision plus noise.

Every family draws its parameters from ``numpy.random.default_rng(seed)``: the same seed gives the
same meshes. All construction is vectorised numpy (or native meshmark calls).
"""
from __future__ import annotations

import numpy as np

from .._core import MeshError
from ..mesh import Mesh

HOLDOUT_FAMILIES = ("torus-tube", "superquadric", "hull-blob")
TRAINING_FAMILIES = ("icosphere", "loop-solid", "heightfield")


def _bumps(rng, D, amp=(0.005, 0.04), n=3):
    """Smooth random relief on directions D (unit vectors, (n, 3)): a sum of n plane waves."""
    out = np.zeros(len(D))
    for _ in range(n):
        k = rng.normal(size=3)
        k *= rng.uniform(1, 7) / np.linalg.norm(k)
        out += rng.uniform(*amp) * np.sin(D @ k + rng.uniform(0, 2 * np.pi))
    return out


def _jitter(rng, V, rel):
    scale = float(np.linalg.norm(V - V.mean(0), axis=1).mean())
    return V + rng.normal(scale=rel * scale, size=V.shape)


def _orient_outward(V, T):
    """Flip triangles of a star-shaped closed surface so that their normals point away from the centre."""
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    flip = np.einsum("ij,ij->i", np.cross(b - a, c - a), (a + b + c) / 3 - V.mean(0)) < 0
    T = T.copy()
    T[flip] = T[flip][:, [0, 2, 1]]
    return T


# --- hold-out families -----------------------------------------------------------------------------

def _torus_tube(rng):
    from .study import procedural_covers
    return procedural_covers(2, seed=int(rng.integers(1 << 31)))[int(rng.integers(2))]  # torus or tube


def _spow(x, e):
    return np.sign(x) * np.abs(x) ** e


def _superquadric(rng):
    nu, nv = int(rng.integers(24, 100)), int(rng.integers(12, 60))
    e1, e2 = rng.uniform(0.3, 2.0, 2)
    u = np.linspace(-np.pi, np.pi, nu, endpoint=False)
    v = np.linspace(-np.pi / 2, np.pi / 2, nv + 2)[1:-1]  # poles are separate vertices
    U, W = np.meshgrid(u, v, indexing="ij")
    P = np.stack([_spow(np.cos(W), e1) * _spow(np.cos(U), e2), _spow(np.cos(W), e1) * _spow(np.sin(U), e2),
                  _spow(np.sin(W), e1)], -1).reshape(-1, 3)
    P = np.vstack([P, [[0, 0, -1], [0, 0, 1]]])
    i = np.arange(nu)[:, None]
    j = np.arange(nv - 1)[None, :]
    a, b = i * nv + j, ((i + 1) % nu) * nv + j
    T = np.concatenate([np.stack([a, b, b + 1], -1).reshape(-1, 3), np.stack([a, b + 1, a + 1], -1).reshape(-1, 3)])
    s, n = nu * nv, np.arange(nu)
    bot = np.stack([np.full(nu, s), ((n + 1) % nu) * nv, n * nv], -1)
    top = np.stack([np.full(nu, s + 1), n * nv + nv - 1, ((n + 1) % nu) * nv + nv - 1], -1)
    T = np.vstack([T, bot, top])
    D = P / np.maximum(np.linalg.norm(P, axis=1, keepdims=True), 1e-12)
    P = P * (1 + _bumps(rng, D))[:, None] * rng.uniform(0.4, 1.5, 3)
    return Mesh(_jitter(rng, P, rng.uniform(0, 1e-3)), T)


def _hull_blob(rng):
    from scipy.spatial import ConvexHull
    n = int(rng.integers(400, 6000))
    D = rng.normal(size=(n, 3))
    D /= np.linalg.norm(D, axis=1, keepdims=True)
    T = ConvexHull(D).simplices.astype(np.int64)
    r = 1 + _bumps(rng, D, amp=(0.02, 0.15), n=4)
    V = D * r[:, None] * rng.uniform(0.5, 1.5, 3)
    return Mesh(_jitter(rng, V, rng.uniform(0, 5e-4)), _orient_outward(D, T))


# --- training-only families ------------------------------------------------------------------------

def _icosahedron():
    t = (1 + 5 ** 0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    T = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                  [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    return V / np.linalg.norm(V, axis=1, keepdims=True), T


def _icosphere(rng):
    from .. import attacks
    V, T = _icosahedron()
    m = attacks.subdivide(V, T, scheme="midpoint", levels=int(rng.integers(2, 6)))
    D = m.V / np.linalg.norm(m.V, axis=1, keepdims=True)
    V = D * (1 + _bumps(rng, D))[:, None] * rng.uniform(0.4, 1.5, 3)
    return Mesh(_jitter(rng, V, rng.uniform(0, 1e-3)), m.F)


def _loop_solid(rng):
    from .. import attacks
    k = int(rng.integers(3))
    if k == 0:  # cube
        V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
        T = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
                      [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    elif k == 1:  # octahedron
        V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
        T = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    else:  # tetrahedron
        V = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
        T = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    V = V * rng.uniform(0.5, 1.5, 3)
    m = attacks.subdivide(V, T, scheme="loop", levels=int(rng.integers(3, 6)))
    D = m.V / np.linalg.norm(m.V, axis=1, keepdims=True)
    return Mesh(_jitter(rng, m.V * (1 + _bumps(rng, D))[:, None], rng.uniform(0, 1e-3)), m.F)


def _heightfield(rng):
    nx, ny = int(rng.integers(20, 90)), int(rng.integers(20, 90))
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, rng.uniform(0.5, 1.5), ny), indexing="ij")
    z = np.zeros_like(x)
    for _ in range(4):
        k = rng.normal(size=2) * rng.uniform(2, 12)
        z += rng.uniform(0.01, 0.08) * np.sin(k[0] * x + k[1] * y + rng.uniform(0, 2 * np.pi))
    V = np.stack([x, y, z], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="ij")
    a = (i * ny + j).ravel()
    b, c, d = a + ny, a + ny + 1, a + 1
    flip = rng.random(a.size) < rng.uniform(0, 0.5)  # random diagonals: valences 4..8
    T1 = np.where(flip[:, None], np.stack([a, b, d], -1), np.stack([a, b, c], -1))
    T2 = np.where(flip[:, None], np.stack([b, c, d], -1), np.stack([a, c, d], -1))
    return Mesh(_jitter(rng, V, rng.uniform(0, 1e-3)), np.concatenate([T1, T2]))


FAMILIES = {"torus-tube": _torus_tube, "superquadric": _superquadric, "hull-blob": _hull_blob,
            "icosphere": _icosphere, "loop-solid": _loop_solid, "heightfield": _heightfield}


def covers(n: int, families, seed: int = 0) -> list[tuple[str, Mesh]]:
    """``n`` meshes ``(name, Mesh)``, cycling through ``families``; reproducible from ``seed``."""
    families = list(families)
    for f in families:
        if f not in FAMILIES:
            raise MeshError(f"unknown generated family {f!r}; choose from {', '.join(FAMILIES)}")
    if n < 0 or not families:
        raise MeshError("need n >= 0 and at least one family")
    out = []
    for i in range(n):
        f = families[i % len(families)]
        rng = np.random.default_rng([seed, i, len(f)])
        out.append((f"{f}#{seed}.{i}", FAMILIES[f](rng)))
    return out


def holdout_covers(n: int, seed: int = 0, families=HOLDOUT_FAMILIES) -> list[tuple[str, Mesh]]:
    """Hold-out covers (never trained on): ``n`` meshes of the hold-out families."""
    bad = set(families) - set(HOLDOUT_FAMILIES)
    if bad:
        raise MeshError(f"{', '.join(sorted(bad))} is a training family, not a hold-out one")
    return covers(n, families, seed)


def training_covers(n: int, seed: int = 0, families=TRAINING_FAMILIES) -> list[tuple[str, Mesh]]:
    """Training-only generated covers: ``n`` meshes of the training families."""
    bad = set(families) - set(TRAINING_FAMILIES)
    if bad:
        raise MeshError(f"{', '.join(sorted(bad))} is a hold-out family, not a training one")
    return covers(n, families, seed)


def open_variants(name: str, mesh: Mesh, seed: int = 0) -> list[tuple[str, Mesh]]:
    """Training-only re-meshings of a cover: a quadric simplification to 20-70 % of the faces, Gaussian
    noise of 0.01-0.3 % of the mean centroid distance, and a midpoint subdivision plus 0.02-0.2 % noise
    (a new, regular-valence vertex set on the same surface). Variants that fail or fall below 50
    vertices are left out."""
    from .. import attacks
    rng = np.random.default_rng(seed)
    out = []
    todo = [("simplify", lambda: attacks.simplify(mesh, fraction=float(rng.uniform(0.2, 0.7)))),
            ("noise", lambda: attacks.noise(mesh, strength=float(10 ** rng.uniform(-4, -2.5)), kind="gaussian",
                                            seed=int(rng.integers(1 << 30)))),
            ("midpoint+noise", lambda: attacks.noise(attacks.subdivide(mesh, scheme="midpoint", levels=1),
                                                     strength=float(10 ** rng.uniform(-3.7, -2.7)),
                                                     kind="gaussian", seed=int(rng.integers(1 << 30))))]
    for tag, make in todo:
        if tag == "midpoint+noise" and mesh.n_vertices > 20000:
            continue
        try:
            m = make()
        except MeshError:
            continue
        if m.n_vertices >= 50:
            out.append((f"{name}#{tag}", m))
    return out
