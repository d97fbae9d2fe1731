"""Reference (oracle) implementations of the mesh attacks used by meshmark.

Pure numpy/scipy, vectorised (no Python loops over vertices or faces; the only
loops are over smoothing iterations, fixed small groups, or chunks).  Meant as
(1) the "numpy/scipy" side of benchmark comparisons and (2) test oracles for the
C++ core.  Definitions and the reasons for each convention are in
docs/attacks.md; thesis = Y. Yang, PhD thesis, Durham 2013
(shared/reference/yang-thesis-2013.txt).

Conventions common to every function
------------------------------------
* ``V`` is a float64 array (N,3); ``F`` an int array (M,3) of triangles.
  Inputs are never modified; new arrays are returned.
* Strengths are fractions, not percent: noise "A = 0.25 %" is ``A=0.0025``.
* Randomness: every random attack takes ``seed`` (int, None or an existing
  ``numpy.random.Generator``) and draws through ``numpy.random.default_rng``.
  The draw order is documented per function, so the same numbers can be
  re-created in numpy; the C++ side cannot reproduce PCG64 streams, so oracle
  tests should either use the deterministic ``*_given`` / ``dither_bits``
  entry points with the random numbers passed in, or compare statistics.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = [
    # helpers
    "as_rng", "unique_edges", "boundary_vertex_mask", "vertex_normals",
    "mean_centroid_distance", "remove_unreferenced",
    # similarity / reordering
    "axis_angle_matrix", "random_rotation_matrix", "rotate", "translate", "scale",
    "similarity_transform", "random_similarity", "permute",
    # noise
    "add_displacement", "uniform_noise", "gaussian_noise", "normal_noise", "tangent_noise",
    # smoothing
    "laplacian_smooth", "cotangent_smooth",
    # quantisation
    "quantize", "dithered_quantize", "dither_bits",
    # connectivity changes
    "midpoint_subdivide", "loop_subdivide", "crop_plane", "simplify_qem", "float32_cast",
]


# ----------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------

def as_rng(seed=None):
    """``numpy.random.default_rng(seed)``, or ``seed`` itself if already a Generator."""
    if isinstance(seed, np.random.Generator):
        return seed
    return np.random.default_rng(seed)


def _as_VF(V, F=None):
    V = np.asarray(V, dtype=np.float64)
    if F is None:
        return V
    return V, np.asarray(F, dtype=np.int64)


def unique_edges(F):
    """Undirected edges of a triangle list.

    Returns ``(E, inv, counts)``: ``E`` (K,2) sorted ``(min,max)`` pairs in
    lexicographic order; ``inv`` (M,3) the edge id of face-edge ``i`` of each face,
    face-edge ``i`` joining corners ``i`` and ``(i+1)%3``; ``counts`` (K,) number of
    incident faces (1 = boundary edge, >2 = non-manifold)."""
    F = np.asarray(F, dtype=np.int64)
    he = np.stack([F, np.roll(F, -1, axis=1)], axis=-1).reshape(-1, 2)
    he = np.sort(he, axis=1)
    E, inv, counts = np.unique(he, axis=0, return_inverse=True, return_counts=True)
    return E, inv.reshape(-1, 3), counts


def _adjacency(nv, F):
    """Binary symmetric vertex adjacency (CSR) from the unique edges of F."""
    E, _, _ = unique_edges(F)
    i = np.concatenate([E[:, 0], E[:, 1]])
    j = np.concatenate([E[:, 1], E[:, 0]])
    return sp.csr_matrix((np.ones(len(i)), (i, j)), shape=(nv, nv))


def boundary_vertex_mask(nv, F):
    """True for vertices incident to an edge used by exactly one face."""
    E, _, counts = unique_edges(F)
    m = np.zeros(nv, bool)
    m[E[counts == 1].ravel()] = True
    return m


def vertex_normals(V, F):
    """Unit vertex normals: sum of the (area-weighted) face cross products
    ``(v1-v0) x (v2-v0)`` of incident faces, normalised.  Vertices with a zero sum
    (unreferenced, or all incident faces degenerate) get the zero vector."""
    V, F = _as_VF(V, F)
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n = np.zeros_like(V)
    for k in range(3):
        np.add.at(n, F[:, k], fn)
    ln = np.linalg.norm(n, axis=1)
    out = np.zeros_like(V)
    ok = ln > 0
    out[ok] = n[ok] / ln[ok, None]
    return out


def mean_centroid_distance(V):
    """d-bar of eq. 6.3.12: mean Euclidean distance of the vertices to their
    arithmetic mean (MEPP Various_Processing convention: all vertices of V)."""
    V = np.asarray(V, dtype=np.float64)
    c = V.mean(axis=0)
    return float(np.linalg.norm(V - c, axis=1).mean())


def remove_unreferenced(V, F):
    """Drop vertices used by no face (order preserved). Returns (V2, F2, kept_old_ids)."""
    V, F = _as_VF(V, F)
    used = np.zeros(len(V), bool)
    used[F.ravel()] = True
    keep = np.nonzero(used)[0]
    remap = -np.ones(len(V), np.int64)
    remap[keep] = np.arange(len(keep))
    return V[keep], remap[F], keep


# ----------------------------------------------------------------------------------------
# similarity transforms and re-ordering (thesis 1.5.2, 6.3.2: "distortionless" attacks)
# ----------------------------------------------------------------------------------------

def axis_angle_matrix(axis, angle_deg):
    """Rotation matrix for a rotation of ``angle_deg`` degrees about ``axis``
    (right-hand rule; same formula as MEPP Various_Processing::Rotation)."""
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    x, y, z = a
    th = np.deg2rad(angle_deg)
    c, s = np.cos(th), np.sin(th)
    return np.array([
        [x * x + (1 - x * x) * c, x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
        [x * y * (1 - c) + z * s, y * y + (1 - y * y) * c, y * z * (1 - c) - x * s],
        [x * z * (1 - c) - y * s, y * z * (1 - c) + x * s, z * z + (1 - z * z) * c],
    ])


def _quat_to_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def random_rotation_matrix(seed=None):
    """Uniformly distributed rotation (Haar measure on SO(3)), Shoemake (1992):
    ``u = rng.random(3)``; ``q = (sqrt(1-u0) sin 2pi u1, sqrt(1-u0) cos 2pi u1,
    sqrt(u0) sin 2pi u2, sqrt(u0) cos 2pi u2)`` as (x,y,z,w)."""
    u = as_rng(seed).random(3)
    a, b = np.sqrt(1 - u[0]), np.sqrt(u[0])
    q = np.array([a * np.sin(2 * np.pi * u[1]), a * np.cos(2 * np.pi * u[1]),
                  b * np.sin(2 * np.pi * u[2]), b * np.cos(2 * np.pi * u[2])])
    return _quat_to_matrix(q)


def rotate(V, axis, angle_deg, center=None):
    """``v' = R (v - c) + c`` with R = axis_angle_matrix; c = origin by default (MEPP)."""
    V = _as_VF(V)
    R = axis_angle_matrix(axis, angle_deg)
    c = np.zeros(3) if center is None else np.asarray(center, dtype=np.float64)
    return (V - c) @ R.T + c


def translate(V, t):
    """``v' = v + t``."""
    return _as_VF(V) + np.asarray(t, dtype=np.float64)


def scale(V, s, center=None):
    """Uniform scaling ``v' = s (v - c) + c``; c = origin by default (MEPP)."""
    V = _as_VF(V)
    c = np.zeros(3) if center is None else np.asarray(center, dtype=np.float64)
    return s * (V - c) + c


def similarity_transform(V, R=None, s=1.0, t=(0.0, 0.0, 0.0)):
    """``v' = s R v + t`` (rotation about the origin, then translation)."""
    V = _as_VF(V)
    R = np.eye(3) if R is None else np.asarray(R, dtype=np.float64)
    return s * (V @ R.T) + np.asarray(t, dtype=np.float64)


def random_similarity(V, seed=None, scale_range=(0.5, 2.0), translation_scale=1.0):
    """Random similarity. Draw order: rotation (3 uniforms, see
    random_rotation_matrix), ``s = exp(rng.uniform(log lo, log hi))``,
    ``t = rng.uniform(-1,1,3) * translation_scale * bbox_diagonal(V)``.
    Returns (V', R, s, t)."""
    V = _as_VF(V)
    rng = as_rng(seed)
    R = random_rotation_matrix(rng)
    s = float(np.exp(rng.uniform(np.log(scale_range[0]), np.log(scale_range[1]))))
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    t = rng.uniform(-1.0, 1.0, 3) * translation_scale * diag
    return similarity_transform(V, R, s, t), R, s, t


def permute(V, F, seed=None, permute_faces=True, rotate_corners=False):
    """Random vertex re-ordering (and face re-ordering) with faces re-indexed.

    Draw order: ``perm = rng.permutation(N)``; then (if permute_faces)
    ``fperm = rng.permutation(M)``; then (if rotate_corners) ``r = rng.integers(0,3,M)``.
    New vertex ``i`` is old vertex ``perm[i]``: ``V' = V[perm]``,
    ``F' = inv(perm)[F][fperm]``, each face optionally cyclically rotated by r
    (orientation preserved).  Returns (V', F', perm, fperm)."""
    V, F = _as_VF(V, F)
    rng = as_rng(seed)
    N, M = len(V), len(F)
    perm = rng.permutation(N)
    inv = np.empty(N, np.int64)
    inv[perm] = np.arange(N)
    F2 = inv[F]
    fperm = rng.permutation(M) if permute_faces else np.arange(M)
    F2 = F2[fperm]
    if rotate_corners:
        r = rng.integers(0, 3, M)
        cols = (np.arange(3)[None, :] + r[:, None]) % 3
        F2 = np.take_along_axis(F2, cols, axis=1)
    return V[perm], F2, perm, fperm


# ----------------------------------------------------------------------------------------
# additive noise (thesis eq. 6.3.12; MEPP NoiseAdditionUniform / NoiseAdditionGaussian)
# ----------------------------------------------------------------------------------------

def add_displacement(V, D, F=None, preserve_boundary=False):
    """Deterministic core of every noise attack: ``v' = v + D``; with
    ``preserve_boundary`` the rows of boundary vertices of F are left unchanged."""
    V = _as_VF(V)
    D = np.asarray(D, dtype=np.float64)
    if preserve_boundary:
        if F is None:
            raise ValueError("preserve_boundary needs F")
        D = D.copy()
        D[boundary_vertex_mask(len(V), F)] = 0.0
    return V + D


def uniform_noise(V, A, seed=None, F=None, preserve_boundary=False):
    """Eq. 6.3.12: ``x_i' = x_i + a_i * d_bar`` (same for y, z), ``a_i ~ U[-A, A]``
    independently per coordinate, ``d_bar = mean_centroid_distance(V)``.
    Draw: ``U = rng.uniform(-1, 1, (N,3))`` (always for all N vertices, even the
    preserved ones); displacement ``A * d_bar * U``."""
    V = _as_VF(V)
    U = as_rng(seed).uniform(-1.0, 1.0, size=V.shape)
    return add_displacement(V, A * mean_centroid_distance(V) * U, F, preserve_boundary)


def gaussian_noise(V, A, seed=None, F=None, preserve_boundary=False):
    """Gaussian variant (MEPP): displacement ``A * d_bar * G``,
    ``G = rng.standard_normal((N,3))`` (sigma = A * d_bar per coordinate)."""
    V = _as_VF(V)
    G = as_rng(seed).standard_normal(size=V.shape)
    return add_displacement(V, A * mean_centroid_distance(V) * G, F, preserve_boundary)


def normal_noise(V, F, A, seed=None, preserve_boundary=False):
    """Noise along the vertex normal only: ``v' = v + A d_bar a_i n_i``,
    ``a = rng.uniform(-1, 1, N)``, n = vertex_normals(V, F) (zero normal -> no move)."""
    V, F = _as_VF(V, F)
    a = as_rng(seed).uniform(-1.0, 1.0, size=len(V))
    n = vertex_normals(V, F)
    return add_displacement(V, (A * mean_centroid_distance(V) * a)[:, None] * n, F,
                            preserve_boundary)


def tangent_noise(V, F, A, seed=None, preserve_boundary=False):
    """Noise in the tangent plane only: ``U = rng.uniform(-1, 1, (N,3))``,
    ``U_t = U - (U.n) n``, ``v' = v + A d_bar U_t``; vertices with a zero normal
    are not moved."""
    V, F = _as_VF(V, F)
    U = as_rng(seed).uniform(-1.0, 1.0, size=V.shape)
    n = vertex_normals(V, F)
    Ut = U - np.sum(U * n, axis=1, keepdims=True) * n
    Ut[np.all(n == 0, axis=1)] = 0.0
    return add_displacement(V, A * mean_centroid_distance(V) * Ut, F, preserve_boundary)


# ----------------------------------------------------------------------------------------
# smoothing (thesis 6.3.2: Laplacian smoothing [175], lambda = 0.02, 10/30/50 iterations)
# ----------------------------------------------------------------------------------------

def laplacian_smooth(V, F, lam=0.02, iterations=10, preserve_boundary=False):
    """Uniform-weight Laplacian smoothing, simultaneous (Jacobi) update, exactly as
    MEPP Various_Processing::LaplacianSmoothing:
    ``v_i <- v_i + lam * (1/|N(i)| sum_{j in N(i)} v_j - v_i)``, N(i) = the distinct
    neighbours of i in the edge graph of F.  Vertices without neighbours do not move;
    with ``preserve_boundary`` boundary vertices do not move."""
    V, F = _as_VF(V, F)
    A = _adjacency(len(V), F)
    deg = np.asarray(A.sum(axis=1)).ravel()
    inv = np.zeros_like(deg)
    inv[deg > 0] = 1.0 / deg[deg > 0]
    fixed = (deg == 0)
    if preserve_boundary:
        fixed |= boundary_vertex_mask(len(V), F)
    move = (~fixed).astype(np.float64)[:, None]
    X = V.copy()
    for _ in range(int(iterations)):
        L = (A @ X) * inv[:, None] - X
        X = X + lam * move * L
    return X


def _cot_weights(X, F):
    """Symmetric cotangent weight matrix: w_ij = max(0, (cot a_ij + cot b_ij)/2),
    a/b = angles opposite edge ij; degenerate corners contribute cot = 0."""
    n = len(X)
    I, J, Wv = [], [], []
    for k in range(3):  # corner k is opposite edge (k+1, k+2)
        i0, i1, i2 = F[:, k], F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        e1 = X[i1] - X[i0]
        e2 = X[i2] - X[i0]
        cr = np.linalg.norm(np.cross(e1, e2), axis=1)
        dt = np.sum(e1 * e2, axis=1)
        cot = np.zeros_like(dt)
        ok = cr > 0
        cot[ok] = dt[ok] / cr[ok]
        I += [i1, i2]
        J += [i2, i1]
        Wv += [0.5 * cot, 0.5 * cot]
    W = sp.csr_matrix((np.concatenate(Wv), (np.concatenate(I), np.concatenate(J))), shape=(n, n))
    W.sum_duplicates()
    W.data = np.maximum(W.data, 0.0)
    return W


def cotangent_smooth(V, F, lam=0.02, iterations=10, preserve_boundary=False):
    """Cotangent-weight variant of laplacian_smooth (explicit, Jacobi):
    ``v_i <- v_i + lam * (sum_j w_ij v_j / sum_j w_ij - v_i)``, weights recomputed
    from the current geometry at every iteration (see _cot_weights: negative edge
    weights clamped to 0).  Where ``sum_j w_ij == 0`` the uniform weights are used."""
    V, F = _as_VF(V, F)
    A = _adjacency(len(V), F)
    deg = np.asarray(A.sum(axis=1)).ravel()
    fixed = (deg == 0)
    if preserve_boundary:
        fixed |= boundary_vertex_mask(len(V), F)
    move = (~fixed).astype(np.float64)[:, None]
    X = V.copy()
    for _ in range(int(iterations)):
        W = _cot_weights(X, F)
        s = np.asarray(W.sum(axis=1)).ravel()
        use_u = (s <= 0) & (deg > 0)
        Wm = W + sp.diags(use_u.astype(np.float64)) @ A
        s = np.asarray(Wm.sum(axis=1)).ravel()
        inv = np.zeros_like(s)
        inv[s > 0] = 1.0 / s[s > 0]
        L = (Wm @ X) * inv[:, None] - X
        X = X + lam * move * L
    return X


# ----------------------------------------------------------------------------------------
# quantisation
# ----------------------------------------------------------------------------------------

def quantize(V, bits, box="axis"):
    """Uniform coordinate quantisation, MEPP Various_Processing::CoordinateQuantization
    (the quantiser of the Wang-Lavoue-Denis-Baskurt 2010 benchmark):

    per axis, ``lo = min``, ``hi = max`` over all vertices, ``step = (hi-lo)/2**bits``,
    ``xint = floor((x-lo)/step)*step + lo``, ``frac = x - xint``,
    ``x' = xint if frac <= 0.5*step else xint + step``  (evaluated in this order in
    float64; no FMA).  I.e. round-to-nearest onto the grid points lo + k*step,
    k = 0..2**bits (2**bits + 1 levels, ties go down).
    ``box="cube"``: one step for all axes, ``max(hi-lo)/2**bits`` (per-axis lo kept).
    An axis with hi == lo is left unchanged."""
    V = _as_VF(V)
    lo = V.min(axis=0)
    hi = V.max(axis=0)
    ext = hi - lo
    if box == "cube":
        ext = np.full(3, ext.max())
    elif box != "axis":
        raise ValueError("box must be 'axis' or 'cube'")
    step = ext / (2.0 ** bits)
    out = V.copy()
    for a in range(3):  # loop over the 3 axes only
        if step[a] <= 0:
            continue
        x = V[:, a]
        xint = np.floor((x - lo[a]) / step[a]) * step[a] + lo[a]
        frac = x - xint
        out[:, a] = np.where(frac <= 0.5 * step[a], xint, xint + step[a])
    return out


def dither_bits(V, t, random_bits, mode="fixed32"):
    """Deterministic core of dithered_quantize: keep the t most significant bits of
    each coordinate word, replace the others by the low bits of ``random_bits``
    (uint64 array shaped like V).  ``t`` may be a scalar or a per-vertex array (N,).
    See dithered_quantize for the two word formats."""
    V = _as_VF(V)
    R = np.asarray(random_bits, dtype=np.uint64)
    t = np.broadcast_to(np.asarray(t, dtype=np.int64).reshape(-1, 1) if np.ndim(t) else
                        np.asarray(t, dtype=np.int64), V.shape)
    if mode == "float64":
        if np.any((t < 0) | (t > 64)):
            raise ValueError("t must be in [0, 64] for float64")
        W = np.ascontiguousarray(V).view(np.uint64)
        nlow = (64 - t).astype(np.uint64)
        # low-bit mask (2**nlow - 1), computed without shifting by 64
        low = np.where(nlow >= 64, np.uint64(0xFFFFFFFFFFFFFFFF),
                       (np.uint64(1) << np.minimum(nlow, 63).astype(np.uint64)) - np.uint64(1))
        out = (W & ~low) | (R & low)
        return out.view(np.float64)
    if mode == "fixed32":
        if np.any((t < 0) | (t > 32)):
            raise ValueError("t must be in [0, 32] for fixed32")
        lo = V.min(axis=0)
        L = float((V.max(axis=0) - lo).max())
        if L <= 0:
            return V.copy()
        s = (V - lo) / L
        q = np.clip(np.floor(s * 2.0 ** 32), 0, 2.0 ** 32 - 1).astype(np.uint64)
        low = (np.uint64(1) << (32 - t).astype(np.uint64)) - np.uint64(1)
        q2 = (q & ~low) | (R & low)
        return lo + L * (q2.astype(np.float64) / 2.0 ** 32)
    raise ValueError("mode must be 'fixed32' or 'float64'")


def dithered_quantize(V, t, seed=None, mode="fixed32"):
    """Dithered quantiser of thesis ch. 3-4: keep the t most significant bits of
    every vertex coordinate and replace all less significant bits by random bits.

    mode="float64" (ch. 3, section 3.2.1): the word is the IEEE-754 binary64 bit
      pattern (sign, 11 exponent bits, 52 mantissa bits, MSB first), t in [0, 64].
      t <= 12 randomises exponent/sign bits, so +-inf/NaN/huge values can occur
      (this is the thesis' "t = 0: all spatial information random" end of the curve).
    mode="fixed32" (ch. 4, sections 4.3.1-4.3.2): the word is a 32-bit unsigned
      fixed-point code of the coordinate in the mesh's bounding cube:
      ``lo = per-axis min``, ``L = max extent`` (one cube, so the dither noise has
      cubic support as assumed in 4.3.1), ``q = min(floor((x-lo)/L * 2**32), 2**32-1)``;
      decoded as ``x' = lo + L * q'/2**32``.  Keeping t bits ~ adding uniform noise of
      edge length L*2**-t (eq. 4.3.19's 2l = 2^-k with coordinates in units of L).
    Draw: ``R = rng.integers(0, 2**64-1, size=(N,3), dtype=uint64, endpoint=True)``
    (full 64-bit words; fixed32 uses their low 32 bits).  ``t`` scalar or (N,)."""
    V = _as_VF(V)
    R = as_rng(seed).integers(0, np.iinfo(np.uint64).max, size=V.shape, dtype=np.uint64,
                              endpoint=True)
    return dither_bits(V, t, R, mode=mode)


# ----------------------------------------------------------------------------------------
# connectivity-changing attacks
# ----------------------------------------------------------------------------------------

def _split_faces(F, nv, inv):
    """1-to-4 split: new vertex of edge e is nv + e; children of face f are rows
    4f..4f+3: [a,m0,m2], [b,m1,m0], [c,m2,m1], [m0,m1,m2] with m0=(a,b), m1=(b,c),
    m2=(c,a)."""
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    m0, m1, m2 = nv + inv[:, 0], nv + inv[:, 1], nv + inv[:, 2]
    ch = np.stack([np.stack([a, m0, m2], 1), np.stack([b, m1, m0], 1),
                   np.stack([c, m2, m1], 1), np.stack([m0, m1, m2], 1)], axis=1)
    return ch.reshape(-1, 3)


def midpoint_subdivide(V, F):
    """One level of midpoint (linear, 1-to-4) subdivision: original vertices kept
    (same ids), one new vertex at the midpoint of every unique edge (ids N + edge id,
    edges in unique_edges order), faces split as in _split_faces."""
    V, F = _as_VF(V, F)
    E, inv, _ = unique_edges(F)
    Vn = np.concatenate([V, 0.5 * (V[E[:, 0]] + V[E[:, 1]])])
    return Vn, _split_faces(F, len(V), inv)


def loop_subdivide(V, F):
    """One level of Loop subdivision (same masks as CGAL Loop_mask_3, used by MEPP):

    * edge with exactly 2 faces: ``3/8 (a+b) + 1/8 (c+d)`` (c,d opposite vertices);
      any other edge (boundary or non-manifold): midpoint ``(a+b)/2``;
    * vertex with no boundary/non-manifold edge, n distinct neighbours:
      ``(1 - n*beta) v + beta * sum(nbrs)``,
      ``beta = (5/8 - (3/8 + 1/4 cos(2 pi/n))**2)/n``  (n = 6 -> 1/16);
    * vertex on exactly two boundary edges: ``3/4 v + 1/8 (p + q)`` (p, q its
      boundary neighbours); other vertices touching boundary/non-manifold edges and
      unreferenced vertices are not moved.
    Topology and numbering as midpoint_subdivide."""
    V, F = _as_VF(V, F)
    nv = len(V)
    E, inv, cnt = unique_edges(F)
    # edge points
    opp_sum = np.zeros((len(E), 3))
    for k in range(3):  # face-edge k joins corners k, k+1; opposite corner k+2
        np.add.at(opp_sum, inv[:, k], V[F[:, (k + 2) % 3]])
    mid = V[E[:, 0]] + V[E[:, 1]]
    interior_e = cnt == 2
    ep = np.where(interior_e[:, None], 0.375 * mid + 0.125 * opp_sum, 0.5 * mid)
    # vertex points
    A = _adjacency(nv, F)
    n = np.asarray(A.sum(axis=1)).ravel()
    nb_sum = A @ V
    special = np.zeros(nv, bool)
    special[E[~interior_e].ravel()] = True
    bE = E[cnt == 1]
    bcount = np.bincount(bE.ravel(), minlength=nv)
    bsum = np.zeros((nv, 3))
    np.add.at(bsum, bE[:, 0], V[bE[:, 1]])
    np.add.at(bsum, bE[:, 1], V[bE[:, 0]])
    vp = V.copy()
    reg = (~special) & (n > 0)
    nn = n[reg]
    beta = (5.0 / 8.0 - (3.0 / 8.0 + 0.25 * np.cos(2 * np.pi / nn)) ** 2) / nn
    vp[reg] = (1 - nn * beta)[:, None] * V[reg] + beta[:, None] * nb_sum[reg]
    bnd = special & (bcount == 2)
    vp[bnd] = 0.75 * V[bnd] + 0.125 * bsum[bnd]
    return np.concatenate([vp, ep]), _split_faces(F, nv, inv)


def crop_plane(V, F, fraction, normal=(1.0, 0.0, 0.0)):
    """Cut off the slab of relative thickness ``fraction`` at the +normal end of the
    mesh: ``s_i = v_i . n`` (n normalised), ``thr = max(s) - fraction*(max(s)-min(s))``
    (max/min over all vertices of V).  A face is kept iff all three of its vertices
    have ``s <= thr`` (no re-triangulation along the cut).  Vertices not used by a
    kept face are removed, order preserved.  Returns (V', F', kept_old_vertex_ids)."""
    V, F = _as_VF(V, F)
    nrm = np.asarray(normal, dtype=np.float64)
    nrm = nrm / np.linalg.norm(nrm)
    s = V @ nrm
    thr = s.max() - fraction * (s.max() - s.min())
    keepf = np.all(s[F] <= thr, axis=1)
    return remove_unreferenced(V, F[keepf])


def float32_cast(V):
    """Round every coordinate to the nearest IEEE binary32 (round-half-even), back to float64."""
    return _as_VF(V).astype(np.float32).astype(np.float64)


def simplify_qem(V, F, face_fraction, **kwargs):
    """Quadric edge-collapse simplification through pymeshlab (NOT numpy; the
    reference for the 'simplification' attack).  Calls
    ``meshing_decimation_quadric_edge_collapse(targetfacenum=round(face_fraction*M),
    **kwargs)`` with pymeshlab defaults otherwise (qualitythr=0.3, optimalplacement,
    autoclean, no boundary/normal/topology preservation).  face_fraction = fraction
    of faces KEPT.  Returns (V', F') (vertex order is pymeshlab's, compacted)."""
    import pymeshlab

    V, F = _as_VF(V, F)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32)))
    ms.meshing_decimation_quadric_edge_collapse(
        targetfacenum=int(round(face_fraction * len(F))), **kwargs)
    m = ms.current_mesh()
    return np.asarray(m.vertex_matrix(), np.float64), np.asarray(m.face_matrix(), np.int64)
