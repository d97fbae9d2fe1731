"""Reference (oracle) implementations of the meshmark distortion / robustness metrics.

Pure numpy/scipy, vectorised (loops only over chunks, the 3 triangle corners or
edge multiplicities).  Definitions, thesis equation numbers and conventions are in
docs/metrics.md.  Angles are in radians unless a name says ``_deg``.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree
from scipy.stats import binom

__all__ = [
    "bbox_diagonal", "vertex_rmse", "face_normals", "face_areas", "min_dihedral_angle_deg",
    "normal_degradation", "dihedral_gaussian_weights",
    "point_triangle_distance", "point_mesh_distance", "point_mesh_distance_bruteforce",
    "sample_surface", "one_sided_distance", "surface_distance", "pymeshlab_hausdorff",
    "to_pm1", "correlation", "normalized_correlation", "bit_error_rate", "cdr",
    "false_alarm_probability",
]


# ----------------------------------------------------------------------------------------
# basic geometry
# ----------------------------------------------------------------------------------------

def bbox_diagonal(V, F=None):
    """Length of the diagonal of the axis-aligned bounding box (of the vertices used
    by F if F is given, else of all vertices)."""
    V = np.asarray(V, np.float64)
    if F is not None:
        V = V[np.unique(np.asarray(F).ravel())]
    return float(np.linalg.norm(V.max(0) - V.min(0)))


def vertex_rmse(V, V2, relative_to=None):
    """Vertex RMSE for meshes in 1-1 vertex correspondence:
    ``sqrt( (1/N) sum_i ||v_i - v'_i||^2 )``; divided by ``relative_to`` if given
    (e.g. bbox_diagonal(V))."""
    d2 = np.sum((np.asarray(V, np.float64) - np.asarray(V2, np.float64)) ** 2, axis=1)
    r = float(np.sqrt(d2.mean()))
    return r / relative_to if relative_to else r


def face_normals(V, F, unit=True):
    """``(v1-v0) x (v2-v0)`` per face (unit length if ``unit``; degenerate -> 0)."""
    V = np.asarray(V, np.float64)
    F = np.asarray(F, np.int64)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    if not unit:
        return n
    ln = np.linalg.norm(n, axis=1)
    out = np.zeros_like(n)
    ok = ln > 0
    out[ok] = n[ok] / ln[ok, None]
    return out


def face_areas(V, F):
    return 0.5 * np.linalg.norm(face_normals(V, F, unit=False), axis=1)


def _edge_face_pairs(F):
    """All pairs (f, g) of distinct faces sharing an undirected edge."""
    F = np.asarray(F, np.int64)
    M = len(F)
    he = np.sort(np.stack([F, np.roll(F, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
    _, eid = np.unique(he, axis=0, return_inverse=True)
    eid = eid.ravel()
    fid = np.repeat(np.arange(M), 3)
    o = np.argsort(eid, kind="stable")
    eid, fid = eid[o], fid[o]
    P, Q = [], []
    d = 1
    while d < len(eid):  # loop over edge multiplicity (2 for manifold meshes)
        same = eid[d:] == eid[:-d]
        if not same.any():
            break
        P.append(fid[:-d][same])
        Q.append(fid[d:][same])
        d += 1
    if not P:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    P, Q = np.concatenate(P), np.concatenate(Q)
    keep = P != Q
    return P[keep], Q[keep]


def min_dihedral_angle_deg(V, F):
    """x_i of eq. 3.2.3: for each face, the smallest angle (degrees, 0 = coplanar,
    180 = folded back) between its normal and the normal of a face sharing an edge
    with it.  Faces with no usable neighbour (all edges boundary, or degenerate
    normals) get +inf."""
    n = face_normals(V, F)
    P, Q = _edge_face_pairs(F)
    ok = np.any(n[P] != 0, axis=1) & np.any(n[Q] != 0, axis=1)
    P, Q = P[ok], Q[ok]
    c = np.sum(n[P] * n[Q], axis=1)
    s = np.linalg.norm(np.cross(n[P], n[Q]), axis=1)
    ang = np.degrees(np.arctan2(s, c))
    x = np.full(len(F), np.inf)
    np.minimum.at(x, P, ang)
    np.minimum.at(x, Q, ang)
    return x


def dihedral_gaussian_weights(V, F, mu=0.0, sigma=3.5):
    """Eq. 3.2.3: ``w_i = exp(-(x_i-mu)^2/(2 sigma^2)) / sqrt(2 pi sigma^2)``,
    x_i = min_dihedral_angle_deg (degrees; see docs/metrics.md for why degrees)."""
    x = min_dihedral_angle_deg(V, F)
    w = np.exp(-((x - mu) ** 2) / (2.0 * sigma ** 2)) / np.sqrt(2.0 * np.pi * sigma ** 2)
    w[~np.isfinite(x)] = 0.0
    return w


def normal_degradation(V, F, V2, weighting="mean", mu=0.0, sigma=3.5, return_details=False):
    """dis(M, M') of eq. 3.2.2 (radians):
    ``sum_i w_i angle(n_i, n'_i) / sum_i w_i`` over the faces of the reference mesh
    M = (V, F) and the attacked mesh M' = (V2, F) (same faces).

    angle = ``atan2(|n x n'|, n . n')`` in [0, pi] (the "smaller angle");
    weighting: "mean" (w=1, dis^av), "area" (w = area of the face in M, dis^ar),
    "dihedral" (eq. 3.2.3 on M, mu=0, sigma=3.5 degrees, dis^an).
    Faces whose normal is zero or non-finite in M or M' are excluded (w=0)."""
    V = np.asarray(V, np.float64)
    V2 = np.asarray(V2, np.float64)
    F = np.asarray(F, np.int64)
    n1 = face_normals(V, F, unit=False)
    with np.errstate(invalid="ignore", over="ignore"):
        n2 = face_normals(V2, F, unit=False)
        valid = (np.all(np.isfinite(n2), axis=1) & np.any(n1 != 0, axis=1)
                 & np.any(n2 != 0, axis=1))
        ang = np.zeros(len(F))
        a, b = n1[valid], n2[valid]
        # scale both to unit length first so that huge n2 cannot overflow
        a = a / np.linalg.norm(a, axis=1, keepdims=True)
        b = b / np.linalg.norm(b, axis=1, keepdims=True)
        ang[valid] = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1))
    if weighting == "mean":
        w = np.ones(len(F))
    elif weighting == "area":
        w = 0.5 * np.linalg.norm(n1, axis=1)
    elif weighting == "dihedral":
        w = dihedral_gaussian_weights(V, F, mu, sigma)
    else:
        raise ValueError("weighting must be 'mean', 'area' or 'dihedral'")
    w = np.where(valid, w, 0.0)
    sw = w.sum()
    val = float(np.sum(w * ang) / sw) if sw > 0 else float("nan")
    if return_details:
        return val, {"angles": ang, "weights": w, "n_excluded": int((~valid).sum())}
    return val


# ----------------------------------------------------------------------------------------
# exact point-to-triangle / point-to-mesh distance
# ----------------------------------------------------------------------------------------

def _seg_d2(P, X, Y):
    d = Y - X
    dd = np.sum(d * d, axis=-1)
    t = np.sum((P - X) * d, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(dd > 0, t / dd, 0.0)
    t = np.clip(t, 0.0, 1.0)
    q = X + t[..., None] * d
    return np.sum((P - q) ** 2, axis=-1), q


def point_triangle_distance(P, A, B, C, return_closest=False):
    """Exact Euclidean distance from points P to triangles (A,B,C) (broadcasting
    arrays of shape (...,3)).  If the orthogonal projection of P on the supporting
    plane lies inside the closed triangle the distance is the plane distance,
    otherwise the minimum of the three segment distances.  Degenerate triangles
    (zero area) reduce to segment distances."""
    P, A, B, C = np.broadcast_arrays(*(np.asarray(x, np.float64) for x in (P, A, B, C)))
    n = np.cross(B - A, C - A)
    nn = np.sum(n * n, axis=-1)
    s0 = np.sum(np.cross(B - A, P - A) * n, axis=-1)
    s1 = np.sum(np.cross(C - B, P - B) * n, axis=-1)
    s2 = np.sum(np.cross(A - C, P - C) * n, axis=-1)
    inside = (s0 >= 0) & (s1 >= 0) & (s2 >= 0) & (nn > 0)
    h = np.sum((P - A) * n, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        dplane2 = np.where(nn > 0, h * h / nn, np.inf)
    d0, q0 = _seg_d2(P, A, B)
    d1, q1 = _seg_d2(P, B, C)
    d2, q2 = _seg_d2(P, C, A)
    dseg = np.minimum(np.minimum(d0, d1), d2)
    dist2 = np.where(inside, dplane2, dseg)
    dist = np.sqrt(dist2)
    if not return_closest:
        return dist
    with np.errstate(invalid="ignore", divide="ignore"):
        proj = P - np.where(nn > 0, h / nn, 0.0)[..., None] * n
    qs = np.where((d0 <= d1)[..., None] & (d0 <= d2)[..., None], q0,
                  np.where((d1 <= d2)[..., None], q1, q2))
    return dist, np.where(inside[..., None], proj, qs)


def point_mesh_distance_bruteforce(P, V, F, chunk_pairs=2_000_000):
    """Exact unsigned distance from each point to the triangle set (all pairs, chunked).
    Returns (dist, face_index).  For small meshes / validation only."""
    P = np.asarray(P, np.float64)
    V = np.asarray(V, np.float64)
    F = np.asarray(F, np.int64)
    A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    step = max(1, chunk_pairs // max(1, len(F)))
    dist = np.empty(len(P))
    fi = np.empty(len(P), np.int64)
    for s in range(0, len(P), step):
        d = point_triangle_distance(P[s:s + step, None, :], A[None], B[None], C[None])
        j = np.argmin(d, axis=1)
        fi[s:s + step] = j
        dist[s:s + step] = d[np.arange(len(j)), j]
    return dist, fi


class _TriangleIndex:
    """Exact point-to-triangle-set distance queries.

    Every triangle j (centroid-to-corner radius r_j) is represented by the centroids
    of the L_j^2 similar sub-triangles of its regular level-L_j split,
    L_j = min(64, ceil(r_j / rho)), rho = median(r)/2, so every point of triangle j
    lies within rho_eff = max_j r_j/L_j of one of its representatives.  A k-d tree is
    built over the representatives.  For a query p with k nearest representatives
    (k-th at distance d_k) and best exact distance ``best`` among their triangles,
    any triangle without a representative among them is at least d_k - rho_eff away,
    so ``best <= d_k - rho_eff`` certifies the result.  Uncertified points are
    re-queried with 4k, 16k, ... representatives until certified (at the end: all)."""

    def __init__(self, V, F):
        V = np.asarray(V, np.float64)
        F = np.asarray(F, np.int64)
        self.M = len(F)
        A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
        self.A = A
        self.AB = B - A
        self.AC = C - A
        self.aa = np.sum(self.AB * self.AB, axis=1)
        self.ab = np.sum(self.AB * self.AC, axis=1)
        self.cc = np.sum(self.AC * self.AC, axis=1)
        nrm = np.cross(self.AB, self.AC)
        nn = np.sum(nrm * nrm, axis=1)
        scale = np.maximum(self.aa, self.cc)
        # (near-)degenerate triangles are handled with the segment-based kernel
        self.degenerate = ~(nn > 1e-24 * scale * scale)
        cen = (A + B + C) / 3.0
        r = np.sqrt(np.max(np.stack([np.sum((X - cen) ** 2, axis=1) for X in (A, B, C)], 1), 1))
        rho = 0.5 * float(np.median(r)) if self.M else 0.0
        if rho > 0:
            L = np.clip(np.ceil(r / rho), 1, 64).astype(np.int64)
        else:
            L = np.ones(self.M, np.int64)
        self.rho_eff = float(np.max(r / L)) if self.M else 0.0
        reps, owner = [], []
        for lv in np.unique(L):  # loop over the few distinct subdivision levels
            t = np.nonzero(L == lv)[0]
            ii, jj = np.meshgrid(np.arange(lv), np.arange(lv), indexing="ij")
            up = (ii + jj) <= lv - 1
            dn = (ii + jj) <= lv - 2
            uv = np.concatenate([np.stack([ii[up] + 1 / 3, jj[up] + 1 / 3], 1),
                                 np.stack([ii[dn] + 2 / 3, jj[dn] + 2 / 3], 1)]) / lv
            R = (A[t, None, :] + uv[None, :, :1] * self.AB[t, None, :]
                 + uv[None, :, 1:] * self.AC[t, None, :])
            reps.append(R.reshape(-1, 3))
            owner.append(np.repeat(t, len(uv)))
        self.owner = np.concatenate(owner) if owner else np.zeros(0, np.int64)
        self.tree = cKDTree(np.concatenate(reps) if reps else np.zeros((0, 3)))
        self.nrep = len(self.owner)

    def _eval(self, p, idx):
        """Exact distance from points p (n,3) to triangles idx (n,): Ericson's
        region-based closest point (Real-Time Collision Detection, 5.1.5), written
        with the per-triangle constants |ab|^2, ab.ac, |ac|^2."""
        a, ab, ac = self.A[idx], self.AB[idx], self.AC[idx]
        aa, abac, cc = self.aa[idx], self.ab[idx], self.cc[idx]
        ap = p - a
        d1 = np.einsum("ij,ij->i", ab, ap)
        d2 = np.einsum("ij,ij->i", ac, ap)
        d3 = d1 - aa
        d4 = d2 - abac
        d5 = d1 - abac
        d6 = d2 - cc
        vc = d1 * d4 - d3 * d2
        vb = d5 * d2 - d1 * d6
        va = d3 * d6 - d5 * d4
        with np.errstate(invalid="ignore", divide="ignore"):
            den = va + vb + vc
            conds = [
                (d1 <= 0) & (d2 <= 0),                                  # vertex A
                (d3 >= 0) & (d4 <= d3),                                 # vertex B
                (vc <= 0) & (d1 >= 0) & (d3 <= 0),                      # edge AB
                (d6 >= 0) & (d5 <= d6),                                 # vertex C
                (vb <= 0) & (d2 >= 0) & (d6 <= 0),                      # edge AC
                (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0),        # edge BC
            ]
            wbc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
            s = np.select(conds, [0.0, 1.0, d1 / (d1 - d3), 0.0, 0.0, 1.0 - wbc], vb / den)
            t = np.select(conds, [0.0, 0.0, 0.0, 1.0, d2 / (d2 - d6), wbc], vc / den)
        q = ap - s[:, None] * ab - t[:, None] * ac
        d = np.sqrt(np.einsum("ij,ij->i", q, q))
        deg = self.degenerate[idx]
        if deg.any():
            b_ = a[deg] + ab[deg]
            c_ = a[deg] + ac[deg]
            d[deg] = point_triangle_distance(p[deg], a[deg], b_, c_)
        return d

    def query(self, P, k=16, chunk_pairs=1_000_000):
        """Exact nearest distance and face id for each point of P (see class doc)."""
        P = np.asarray(P, np.float64)
        n = len(P)
        dist = np.full(n, np.inf)
        fid = np.full(n, -1, np.int64)
        todo = np.arange(n)
        k = int(min(max(k, 1), self.nrep))
        while todo.size:
            step = max(1, chunk_pairs // k)
            left = []
            for s in range(0, len(todo), step):   # chunks of points, bounded memory
                t = todo[s:s + step]
                p = P[t]
                dc, ir = self.tree.query(p, k)
                dc = dc.reshape(len(t), k)
                tri = self.owner[ir.reshape(len(t), k)]
                # evaluate each distinct (point, triangle) pair once
                ts = np.sort(tri, axis=1)
                first = np.ones(ts.shape, bool)
                first[:, 1:] = ts[:, 1:] != ts[:, :-1]
                rows, cols = np.nonzero(first)
                d = np.full(ts.shape, np.inf)
                d[rows, cols] = self._eval(p[rows], ts[rows, cols])
                tri = ts
                j = np.argmin(d, axis=1)
                r = np.arange(len(t))
                dist[t] = d[r, j]
                fid[t] = tri[r, j]
                if k < self.nrep:
                    left.append(t[dist[t] > dc[:, -1] - self.rho_eff])
            todo = np.concatenate(left) if left else np.zeros(0, np.int64)
            k = min(4 * k, self.nrep)
        return dist, fid


def point_mesh_distance(P, V, F, k=16):
    """Exact unsigned distance from each point of P to the surface (V,F) (union of its
    closed triangles), using a centroid k-d tree with a certified bound (see
    _TriangleIndex.query).  Returns (dist, face_index)."""
    return _TriangleIndex(V, F).query(P, k=k)


# ----------------------------------------------------------------------------------------
# Metro-style surface distance
# ----------------------------------------------------------------------------------------

def sample_surface(V, F, n, seed=None):
    """n points uniformly distributed by area on the triangles (V,F).
    Draw order: ``r = rng.random(n)`` (face choice by inverse CDF of the cumulated
    areas, ``searchsorted(cumsum(area), r*total, 'right')``), then ``u = rng.random(n)``,
    ``v = rng.random(n)``; if u+v > 1: (u,v) <- (1-u, 1-v); point = a + u(b-a) + v(c-a).
    Returns (points, face_ids)."""
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    V = np.asarray(V, np.float64)
    F = np.asarray(F, np.int64)
    cdf = np.cumsum(face_areas(V, F))
    r = rng.random(n)
    fi = np.minimum(np.searchsorted(cdf, r * cdf[-1], side="right"), len(F) - 1)
    u = rng.random(n)
    v = rng.random(n)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    A, B, C = V[F[fi, 0]], V[F[fi, 1]], V[F[fi, 2]]
    return A + u[:, None] * (B - A) + v[:, None] * (C - A), fi


def one_sided_distance(VA, FA, VB, FB, n_samples=None, include_vertices=True, seed=0,
                       return_samples=False):
    """Distances from samples of surface A to surface B (Metro/MeshLab 'Hausdorff
    Distance' with SampleVert + SampleFace).  Samples = every vertex of A referenced by
    FA (if include_vertices) + ``n_samples`` area-uniform points (default
    10 * len(FA)).  Returns dict with max, mean, rms, min, n."""
    VA = np.asarray(VA, np.float64)
    FA = np.asarray(FA, np.int64)
    if n_samples is None:
        n_samples = 10 * len(FA)
    pts = []
    if include_vertices:
        pts.append(VA[np.unique(FA.ravel())])
    if n_samples > 0:
        pts.append(sample_surface(VA, FA, int(n_samples), seed)[0])
    S = np.concatenate(pts)
    d, _ = point_mesh_distance(S, VB, FB)
    out = {"max": float(d.max()), "mean": float(d.mean()), "rms": float(np.sqrt(np.mean(d * d))),
           "min": float(d.min()), "n": int(len(d))}
    if return_samples:
        out["samples"], out["dist"] = S, d
    return out


def surface_distance(VA, FA, VB, FB, n_samples=None, include_vertices=True, seed=0):
    """Symmetric Metro-style distance between the reference A and the attacked B.

    hausdorff = max(h(A,B), h(B,A)) (max of the one-sided maxima);
    mrms      = max(rms(A,B), rms(B,A)) (Wang et al. 2010 "MRMS");
    mean      = max of the one-sided means; *_rel = value / bbox_diagonal(A).
    Sample counts per direction: n_samples (default 10 x faces of the sampled mesh)
    + referenced vertices.  seed for A->B, seed+1 for B->A."""
    ab = one_sided_distance(VA, FA, VB, FB, n_samples, include_vertices, seed)
    ba = one_sided_distance(VB, FB, VA, FA, n_samples, include_vertices,
                            None if seed is None else seed + 1)
    diag = bbox_diagonal(VA, FA)
    h = max(ab["max"], ba["max"])
    r = max(ab["rms"], ba["rms"])
    m = max(ab["mean"], ba["mean"])
    return {"ab": ab, "ba": ba, "hausdorff": h, "mrms": r, "mean": m, "diag": diag,
            "hausdorff_rel": h / diag, "mrms_rel": r / diag, "mean_rel": m / diag}


def pymeshlab_hausdorff(VA, FA, VB, FB, samplenum=None, samplevert=True, sampleface=True,
                        sampleedge=False, maxdist=None, savesample=False):
    """One-sided distance A -> B with pymeshlab's get_hausdorff_distance (the calling
    convention documented in docs/metrics.md).  A is the *sampled* mesh, B the target.
    maxdist default: 4 x the larger bbox diagonal (nothing is rejected).  Returns the
    pymeshlab dict (keys RMS, max, mean, min, n_samples, diag_mesh_0, diag_mesh_1) and,
    with savesample, also 'samples' and 'closest' point arrays and 'dist'."""
    import pymeshlab

    VA, VB = np.asarray(VA, np.float64), np.asarray(VB, np.float64)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(VA, np.asarray(FA, np.int32)))   # id 0: sampled
    ms.add_mesh(pymeshlab.Mesh(VB, np.asarray(FB, np.int32)))   # id 1: target
    if samplenum is None:
        samplenum = 10 * len(FA)
    if maxdist is None:
        maxdist = 4.0 * max(bbox_diagonal(VA), bbox_diagonal(VB))
    r = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, savesample=savesample,
                                  samplevert=samplevert, sampleedge=sampleedge,
                                  samplefauxedge=False, sampleface=sampleface,
                                  samplenum=int(samplenum),
                                  maxdist=pymeshlab.PureValue(float(maxdist)))
    r = dict(r)
    if savesample:
        # layers added: 2 = "Hausdorff Closest Points", 3 = "Hausdorff Sample Point"
        r["closest"] = ms.mesh(2).vertex_matrix().copy()
        r["samples"] = ms.mesh(3).vertex_matrix().copy()
        r["dist"] = ms.mesh(3).vertex_scalar_array().copy()
    return r


# ----------------------------------------------------------------------------------------
# watermark detection metrics
# ----------------------------------------------------------------------------------------

def to_pm1(w):
    """Map bits to symbols: {0,1} -> {-1,+1}; values already in {-1,+1} pass through."""
    w = np.asarray(w)
    if w.dtype == bool or np.all((w == 0) | (w == 1)):
        return 2.0 * w.astype(np.float64) - 1.0
    return w.astype(np.float64)


def correlation(w, w2):
    """Eq. 6.3.11 (Pearson correlation of the two sequences):
    ``sum (w_i - wbar)(w'_i - w'bar) / sqrt(sum (w_i-wbar)^2 sum (w'_i-w'bar)^2)``.
    Invariant to the {0,1}/{-1,+1} coding.  NaN if either sequence is constant."""
    a = np.asarray(w, np.float64)
    b = np.asarray(w2, np.float64)
    a = a - a.mean()
    b = b - b.mean()
    den = np.sqrt(np.sum(a * a) * np.sum(b * b))
    return float(np.sum(a * b) / den) if den > 0 else float("nan")


def normalized_correlation(w, w2):
    """NC (thesis 7.4.2, not given by an equation there): un-centred correlation of
    the +-1 symbols, ``sum s_i s'_i / sqrt(sum s_i^2 sum s'_i^2)`` = 1 - 2 BER."""
    a, b = to_pm1(w), to_pm1(w2)
    return float(np.sum(a * b) / np.sqrt(np.sum(a * a) * np.sum(b * b)))


def bit_error_rate(w, w2):
    """Fraction of positions where the two bit strings differ (after to_pm1)."""
    return float(np.mean(to_pm1(w) != to_pm1(w2)))


def cdr(w, w2):
    """Correct detection rate (thesis 7.4.2) = fraction of equal bits = 1 - BER."""
    return 1.0 - bit_error_rate(w, w2)


def false_alarm_probability(n, matches):
    """P(X >= matches), X ~ Binomial(n, 1/2): probability that a random (unmarked)
    n-bit string agrees with the watermark in at least ``matches`` positions."""
    return float(binom.sf(int(matches) - 1, int(n), 0.5))
