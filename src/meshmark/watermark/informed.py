"""Informed tracing: a keyed low-pass pattern per issued copy, read back with the original.

Each issued copy j carries, beside its blind codeword, the displacement ``a_j (H w_j)_i n_i`` of every
(welded, referenced) vertex i along the original's unit normal n_i, where

* ``w_j`` is an i.i.d. standard normal field keyed by the owner's key, the asset's digest and the
  copy id (:func:`copy_seed`, ``meshmark._core.keyed_gaussians``);
* ``H = (A^-1 M)^k M^-1/2`` with ``A = M + t L`` (``meshmark._core.LowpassOperator``: lumped mass M
  normalised to mean 1, cotangent stiffness L): a smooth field, cut off near mode ``n / (4 pi t)``;
* ``a_j`` scales the displacement to vertex RMSE ``rmse`` x the bounding-box diagonal.

Detection (:func:`detect`) aligns the suspect to the original (similarity with scale, trimmed ICP from
the 24 proper PCA frames), measures the residual r along the original's normals (same vertices when
the count and order survive, else the closest point of the suspect's surface to each original
vertex), removes the part explained by the rigid-alignment error and by the shape change of
smoothing and subdivision simulated on the original (least squares on a few columns computed from
the original alone), masks and clips outliers, filters ``u = H^T r`` and correlates::

    z_j = <u, w_j> / ||u||

Every step before the correlation depends only on the suspect and the original, so for every copy j
whose pattern is not in the suspect, w_j is independent of u and z_j ~ N(0, 1) exactly, whatever the
suspect is (unmarked, another copy, another asset, attacked). The false-alarm probability of naming
the best of N copies is therefore at most ``N * Q(z_max)`` with Q the standard normal tail
(Bonferroni). See docs/tracing.md.
"""
from __future__ import annotations

import hashlib
import hmac
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .. import _core
from .._core import MeshError
from ..mesh import Mesh

VERSION = 1
# Defaults (docs/tracing.md, "Choosing the pattern"): about 240 modes below the cut-off, second power
DEFAULT_MODES = 240
DEFAULT_POWER = 2
DEFAULT_RMSE = 6e-5           # vertex RMSE of the pattern / bounding-box diagonal
_BATCH = 16                   # copies per low-pass solve (memory: n x 16 doubles)
# the alignment's starts are scored and refined on every k-th triangle of the original, about this
# many (docs/tracing.md, Speed): most of the 76 starts put the points far from the surface, where a
# closest-point query costs about 10x a near one; the fine stage uses every triangle
COARSE_TRIANGLES = 8000


def _tri(mesh: Mesh) -> np.ndarray:
    return np.ascontiguousarray(mesh.triangles, np.int32)


def copy_seed(key: str, asset_sha: str, copy_id: str) -> int:
    """64-bit seed of copy ``copy_id``'s field w_j: HMAC-SHA256(key, 'meshmark-informed-1|sha|id')."""
    msg = f"meshmark-informed-{VERSION}|{asset_sha}|{copy_id}".encode()
    return int.from_bytes(hmac.new(key.encode(), msg, hashlib.sha256).digest()[:8], "little")


def default_params(mesh: Mesh) -> dict:
    """The pattern parameters recorded in the asset's setup (``setup['informed']``)."""
    n = int(np.unique(mesh.face_indices).size)
    return {"version": VERSION, "modes": DEFAULT_MODES, "power": DEFAULT_POWER, "rmse": DEFAULT_RMSE,
            "t": n / (4.0 * math.pi * DEFAULT_MODES)}


def check_params(p) -> dict:
    if not isinstance(p, dict) or p.get("version") != VERSION:
        raise MeshError(f"the registry's informed pattern settings are not version {VERSION}: {p!r}")
    try:
        t, k, rm = float(p["t"]), int(p["power"]), float(p["rmse"])
    except (KeyError, TypeError, ValueError):
        raise MeshError(f"the registry's informed pattern settings are incomplete: {p!r}") from None
    if not (t > 0 and math.isfinite(t) and 1 <= k <= 8 and 0 < rm < 0.01):
        raise MeshError(f"the registry's informed pattern settings are out of range: {p!r}")
    return {**p, "t": t, "power": k, "rmse": rm}


class Original:
    """The welded original with what issuing and detection need: triangles, unit normals, diagonal,
    and, each built on first use and kept, the low-pass operator, the triangle tree of the alignment
    and the shape columns of detection."""

    def __init__(self, mesh: Mesh, params: dict):
        self.mesh = mesh
        self.params = check_params(params)
        self.T = np.ascontiguousarray(_tri(mesh), np.int32)
        self.V = np.ascontiguousarray(mesh.V, np.float64)
        self.N = _core.vertex_normals(self.V, self.T)
        self.ref = np.zeros(len(self.V), bool)
        self.ref[self.T.ravel()] = True
        P = self.V[self.ref]
        self.diag = float(np.linalg.norm(P.max(0) - P.min(0)))
        self.edge = float(np.median(np.linalg.norm(self.V[self.T] - self.V[np.roll(self.T, 1, axis=1)], axis=2)))
        self._op = self._tree = self._coarse = self._B = None

    @property
    def op(self):
        if self._op is None:
            self._op = _core.LowpassOperator(self.V, self.T, self.params["t"], self.params["power"])
        return self._op

    @property
    def tree(self):
        """The bounding-box tree of the original's triangles (every alignment step queries it)."""
        if self._tree is None:
            self._tree = _core.TriangleTree(self.V, self.T)
        return self._tree

    @property
    def coarse_tree(self):
        """The tree of every k-th triangle (about COARSE_TRIANGLES; all of them on smaller meshes), on
        which the alignment scores and refines its starts."""
        if self._coarse is None:
            k = len(self.T) // COARSE_TRIANGLES
            self._coarse = self.tree if k < 2 else _core.TriangleTree(self.V, np.ascontiguousarray(self.T[::k]))
        return self._coarse

    def patterns(self, seeds) -> np.ndarray:
        """(n, N) normal displacements of the copies with these seeds, each at the recorded RMSE."""
        seeds = [int(s) for s in seeds]
        out = np.empty((len(self.V), len(seeds)))
        n_ref = max(int(self.ref.sum()), 1)
        for b in range(0, len(seeds), _BATCH):
            P = self.op.apply(_core.keyed_gaussians(seeds[b:b + _BATCH], len(self.V)))
            rms = np.sqrt((P * P).sum(0) / n_ref)
            out[:, b:b + _BATCH] = P * (self.params["rmse"] * self.diag / np.where(rms > 0, rms, 1.0))
        return out

    def marked(self, d: np.ndarray) -> np.ndarray:
        """Vertices displaced by d (n,) along the normals."""
        return self.V + d[:, None] * self.N

    # --- detection helpers ------------------------------------------------------------------------
    def shape_columns(self) -> np.ndarray:
        """(n, 11) normal components the residual is cleaned of: rigid-alignment error (translation 3,
        scale 1, rotation 3) and the shape change of smoothing (uniform umbrella, its square, cotangent
        umbrella) and of one Loop step (the vertex points), all on the original (computed once)."""
        if self._B is None:
            self._B = self._shape_columns()
        return self._B

    def _shape_columns(self) -> np.ndarray:
        V, N, T = self.V, self.N, self.T
        c = V[self.ref].mean(0)
        X = V - c
        cols = [N[:, 0], N[:, 1], N[:, 2], (X * N).sum(1)]
        cols += list(np.cross(X, N).T)
        idx, off = self.mesh.face_indices, self.mesh.face_offsets
        D1 = _core.laplacian_smooth(V, idx, off, 1.0, 1, False) - V
        D2 = _core.laplacian_smooth(D1, idx, off, 1.0, 1, False) - D1
        Dc = _core.cotangent_smooth(V, T, 1.0, 1, False) - V
        Vl, _ = _core.loop_subdivide(V, T)
        Dl = Vl[:len(V)] - V
        cols += [(D * N).sum(1) for D in (D1, D2, Dc, Dl)]
        B = np.column_stack(cols)
        B[~self.ref] = 0
        return B


_ROTATIONS = None


def proper_axis_rotations() -> list:
    """The 24 rotations that map the coordinate axes onto signed coordinate axes."""
    global _ROTATIONS
    if _ROTATIONS is None:
        import itertools

        R = []
        for perm in itertools.permutations(range(3)):
            for signs in itertools.product((1, -1), repeat=3):
                M = np.zeros((3, 3))
                M[range(3), perm] = signs
                if np.linalg.det(M) > 0:
                    R.append(M)
        _ROTATIONS = R
    return _ROTATIONS


def _frame(P):
    c = P.mean(0)
    C = np.cov((P - c).T)
    w, Q = np.linalg.eigh(C)
    return c, Q[:, ::-1], max(float(w.sum()), 1e-300)


def _subsample(n: int, m: int) -> np.ndarray:
    if n <= m:
        return np.arange(n)
    return np.sort(np.random.default_rng(12345).choice(n, m, replace=False))


def align(suspect: Mesh, orig: Original, coarse_points: int = 400, fine_points: int = 4000) -> dict:
    """Similarity (4x4, suspect -> original frame) by trimmed ICP from 76 starts (below), the 6 best
    refined (both on ``orig.coarse_tree``), the best of those with scale and point-to-plane steps on
    every triangle. Returns ``{"matrix", "rms", "kept", "start"}``."""
    Ts = _tri(suspect)
    used = np.unique(Ts.ravel())
    if used.size < 3:
        raise MeshError("the suspect mesh has fewer than 3 referenced vertices")
    S = suspect.V[used]
    cs, Qs, vs = _frame(S)
    co, Qo, vo = _frame(orig.V[orig.ref])
    s0 = math.sqrt(vo / vs)
    # starts: the identity (a suspect left in place) and the 24 proper PCA frames, each with the
    # centroids together and shifted by half a standard deviation either way along the original's
    # first axis (a cropped suspect's centroid is not the original's), at the PCA scale
    lam1 = math.sqrt(max(float(np.var((orig.V[orig.ref] - co) @ Qo[:, 0])), 0.0))
    rots = [np.eye(3)]
    for Rk in proper_axis_rotations():
        R = Qo @ Rk @ Qs.T
        if np.linalg.det(R) < 0:
            R = Qo @ Rk @ np.diag([1, 1, -1]) @ Qs.T
        rots.append(R)
    starts = [np.eye(4)]  # the suspect left in place, at its own scale (a pose: one part still fits)
    for R in rots:
        for shift in (0.0, -0.5, 0.5):
            A = np.eye(4)
            A[:3, :3] = s0 * R
            A[:3, 3] = co + shift * lam1 * Qo[:, 0] - s0 * R @ cs
            starts.append(A)
    Pc = np.ascontiguousarray(S[_subsample(len(S), coarse_points)])
    # rigid at the PCA scale from every start, then with scale, kept within [0.6, 1.6] x the PCA scale
    # (a suspect shrunk onto the surface would otherwise fit it perfectly)
    A, rms, kept, _, start = _core.align_similarity(Pc, orig.coarse_tree, starts, 3, 0, 0.5, False, top=6, refine=12)
    Pf = np.ascontiguousarray(S[_subsample(len(S), fine_points)])
    # the fine stage keeps the best-fitting half: a posed suspect's fit locks onto one rigid part
    A, rms, kept, _, _ = _core.align_similarity(Pf, orig.tree, [A], 1, 10, 0.5, True, 0.6 * s0, 1.6 * s0)
    return {"matrix": A, "rms": float(rms), "kept": float(kept), "start": int(start)}


def _correspondence(suspect: Mesh, orig: Original, A: np.ndarray):
    """The suspect's point Q_i (n, 3) matched to each original vertex after the similarity A, its
    squared distance and ``"identity"`` (the same vertices: when the counts agree and they are still
    within a quarter of an edge of their originals; a reordered copy's are edges apart, and the
    nearest points of a noisy surface are biased) or ``"closest-point"``."""
    Vs = suspect.V @ A[:3, :3].T + A[:3, 3]
    if suspect.n_vertices == orig.mesh.n_vertices:
        di = np.linalg.norm(Vs - orig.V, axis=1)[orig.ref]
        if np.median(di) <= 0.25 * orig.edge:
            return Vs, (Vs - orig.V) ** 2 @ np.ones(3), "identity"
    Ts = np.ascontiguousarray(_tri(suspect), np.int32)
    Q, _, _, d2 = _core.closest_points(orig.V, np.ascontiguousarray(Vs), Ts)
    return Q, d2, "closest-point"


def detect(suspect: Mesh, orig: Original, seeds, return_u: bool = False) -> dict:
    """Correlations z_j of the suspect's residual against the copies' fields (see the module doc).

    Returns ``{"z": (N,) array, "correspondence": "identity" | "closest-point", "n_used": vertices
    used, "alignment_rms": RMS distance / diagonal, "scale": the suspect -> original scale}`` and, with
    ``return_u``, the filtered residual ``"u"`` (n,)."""
    # what depends on the original alone (the factorisation of M + t L, the shape columns) is built in
    # a second thread while the alignment runs (both release the GIL)
    with ThreadPoolExecutor(1) as pool:
        prep = pool.submit(lambda: (orig.op, orig.shape_columns()))
        al = align(suspect, orig)
        A = al["matrix"]
        Q, d2, corr = _correspondence(suspect, orig, A)
        prep.result()
    D = Q - orig.V
    r = (D * orig.N).sum(1)
    dist = np.sqrt(d2)
    # correspondence mask: referenced, finite, not far beyond the distance of the best-matched fifth
    # (cropped parts and parts the similarity does not align are far; their nearest points lie on the
    # suspect's cut, mostly sideways)
    base = orig.ref & np.isfinite(dist)
    q20 = float(np.quantile(dist[base], 0.2)) if base.any() else 0.0
    thr = 8.0 * q20 + 1e-9 * orig.diag
    tang = np.linalg.norm(D - r[:, None] * orig.N, axis=1)
    mask = base & (dist <= thr) & (tang <= thr)
    n_used = int(mask.sum())
    if n_used < 16:
        out = {"z": np.zeros(len(seeds)), "correspondence": corr, "n_used": n_used,
               "alignment_rms": al["rms"] / orig.diag, "scale": float(np.cbrt(np.linalg.det(A[:3, :3])))}
        if return_u:
            out["u"] = np.zeros(len(orig.V))
        return out
    B = orig.shape_columns()
    m = orig.op.mass
    wts = np.sqrt(m[mask])
    Bm = B[mask] * wts[:, None]
    beta, *_ = np.linalg.lstsq(Bm, r[mask] * wts, rcond=None)
    rr = np.where(mask, r - B @ beta, 0.0)
    # robust trimming: the residual's scale by the median absolute deviation; zero beyond 8 sigma,
    # clip at 3 sigma
    sig = 1.4826 * float(np.median(np.abs(rr[mask]))) + 1e-15 * orig.diag
    rr = np.where(np.abs(rr) > 8 * sig, 0.0, np.clip(rr, -3 * sig, 3 * sig))
    u = orig.op.apply_transpose(rr[:, None])[:, 0]
    nu = float(np.linalg.norm(u))
    z = _core.keyed_gaussian_dots(u, [int(s) for s in seeds]) / nu if nu > 0 else np.zeros(len(seeds))
    out = {"z": np.asarray(z), "correspondence": corr, "n_used": n_used,
           "alignment_rms": al["rms"] / orig.diag, "scale": float(np.cbrt(np.linalg.det(A[:3, :3])))}
    if return_u:
        out["u"] = u
    return out


def tail_probability(z: float) -> float:
    """Q(z) = P(N(0,1) >= z)."""
    return 0.5 * math.erfc(z / math.sqrt(2.0))


# --- finding the original -------------------------------------------------------------------------

def source_digest(mesh) -> str:
    """SHA-256 of a (welded) mesh's float64 vertices and faces: identifies the original."""
    h = hashlib.sha256(np.ascontiguousarray(mesh.V, np.float64).tobytes())
    h.update(np.ascontiguousarray(mesh.face_indices, np.int64).tobytes())
    h.update(np.ascontiguousarray(mesh.face_offsets, np.int64).tobytes())
    return h.hexdigest()


def _welded(mesh: Mesh, weld: bool) -> Mesh:
    from ..topology import weld_vertices

    return weld_vertices(mesh).mesh if weld else mesh


def find_original(reg, asset_id: int, setup: dict, given=None):
    """The asset's :class:`Original` and a status dict ``{"asset_id", "path", "status"}``; status is
    ``"given"`` or ``"recorded"`` (used), or ``"not recorded"``, ``"missing"``, ``"unreadable"``,
    ``"digest mismatch"``, ``"no pattern"`` (not used: blind evidence only). ``given``: a Mesh already
    read (its digest is checked here), or None."""
    from ..io import read_mesh

    path, resolved, sha = reg.original(asset_id)
    info = {"asset_id": asset_id, "path": path, "status": "not recorded"}
    if not setup.get("informed"):
        info["status"] = "no pattern"
        return None, info
    mesh = None
    if given is not None:
        cand = _welded(given, bool(setup["weld"]))
        if source_digest(cand) == sha:
            info.update(status="given", path=None)
            mesh = cand
        elif path is None:
            info["status"] = "digest mismatch"
            return None, info
    if mesh is None:
        if path is None:
            return None, info
        import os

        where = resolved if resolved and os.path.isfile(resolved) else path
        if not os.path.isfile(where):
            info["status"] = "missing"
            return None, info
        try:
            cand = _welded(read_mesh(where), bool(setup["weld"]))
        except (MeshError, OSError):
            info["status"] = "unreadable"
            return None, info
        if source_digest(cand) != sha:
            info["status"] = "digest mismatch"
            return None, info
        info.update(status="recorded", path=where)
        mesh = cand
    return Original(mesh, setup["informed"]), info
