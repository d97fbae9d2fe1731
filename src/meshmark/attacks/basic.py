"""The attacks on positions, order and connectivity (see :mod:`meshmark.attacks` for the overview)."""
from __future__ import annotations

import math
import os
import tempfile

import numpy as np

from .. import _core
from .._core import MeshError
from ..mesh import as_mesh, FacesLike, Mesh, MeshLike, _as_vertices
from .._typing import ArrayLike, FloatArray, IntArray

__all__ = [
    "rotate", "translate", "scale", "similarity", "random_rotation", "reorder", "noise", "smooth",
    "quantize", "dither", "dithered_quantize", "dither_bits", "simplify", "subdivide", "crop",
    "float32_cast", "file_roundtrip", "mean_centroid_distance", "vertex_normals", "NOISE_KINDS",
]

NOISE_KINDS = ("uniform", "gaussian", "normal", "tangent")
_UINT64 = 2 ** 64


def _seed(seed) -> int:
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise MeshError(f"seed must be an integer, got {seed!r}")
    if not 0 <= int(seed) < _UINT64:
        raise MeshError(f"seed must be in 0 .. 2^64 - 1, got {seed}")
    return int(seed)


def _finite(x, name: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise MeshError(f"{name} must be a number, got {x!r}") from None
    if not math.isfinite(v):
        raise MeshError(f"{name} must be finite, got {v}")
    return v


def _vec3(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise MeshError(f"{name} must be 3 finite numbers, got {x!r}")
    return a


def _tri(m: Mesh) -> np.ndarray:
    return np.ascontiguousarray(m.triangles, dtype=np.int32)


def _same_faces(m: Mesh, V: np.ndarray) -> Mesh:
    return Mesh.from_polygons(V, m.face_indices, m.face_offsets, validate=False)


def _referenced(m: Mesh) -> np.ndarray:
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    return used


# --- similarity transforms ("distortionless", thesis 1.5.2 / 6.3.2) ----------------------------------

def rotate(V: MeshLike, F: FacesLike = None, *, axis: ArrayLike = (0.0, 0.0, 1.0), angle: float = 30.0,
           center: ArrayLike | None = None) -> Mesh:
    """Rotate by ``angle`` degrees about ``axis`` (right-hand rule) through ``center`` (default the origin).

    ``v' = R (v - c) + c``. Returns a Mesh with the same faces.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    ``axis``: (3,) direction; ``center``: (3,) point in mesh units.
    """
    m = as_mesh(V, F)
    R = _core.axis_angle_rotation(_vec3(axis, "axis"), _finite(angle, "angle"))
    c = np.zeros(3) if center is None else _vec3(center, "center")
    return _same_faces(m, _core.similarity_transform(m.V, R, 1.0, c - R @ c))


def translate(V: MeshLike, F: FacesLike = None, *, offset: ArrayLike) -> Mesh:
    """``v' = v + offset`` (offset: 3 numbers, model units).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    m = as_mesh(V, F)
    return _same_faces(m, _core.similarity_transform(m.V, np.eye(3), 1.0, _vec3(offset, "offset")))


def scale(V: MeshLike, F: FacesLike = None, *, factor: float, center: ArrayLike | None = None) -> Mesh:
    """Uniform scaling ``v' = factor (v - c) + c`` (c default the origin). MeshError unless factor > 0.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    m = as_mesh(V, F)
    s = _finite(factor, "scale factor")
    if s <= 0:
        raise MeshError(f"scale factor must be > 0, got {s}")
    c = np.zeros(3) if center is None else _vec3(center, "center")
    return _same_faces(m, _core.similarity_transform(m.V, np.eye(3), s, c - s * c))


def random_rotation(seed: int = 0) -> np.ndarray:
    """(3, 3) uniformly distributed rotation (Shoemake's method) drawn with ``seed``."""
    R, _, _ = _core.random_similarity_params(_seed(seed), 0.0, 0.0)
    return R


def similarity(V: MeshLike, F: FacesLike = None, *, seed: int = 0, scale_range: tuple[float, float] = (0.5, 2.0),
               translation: float = 1.0,
               return_transform: bool = False) -> Mesh | tuple[Mesh, FloatArray, float, FloatArray]:
    """Random similarity ``v' = s R v + t``.

    R uniform on SO(3); ``s = exp(U[log lo, log hi])`` with ``scale_range = (lo, hi)``;
    ``t = U[-1, 1]^3 * translation * bbox diagonal`` (of the referenced vertices). Draw order:
    rotation, scale, translation. With ``return_transform`` returns ``(mesh, R (3,3), s, t (3,))``.
    """
    m = as_mesh(V, F)
    lo, hi = (_finite(x, "scale_range") for x in scale_range)
    if not 0 < lo <= hi:
        raise MeshError(f"scale_range must satisfy 0 < lo <= hi, got ({lo}, {hi})")
    tr = _finite(translation, "translation")
    R, s, t = _core.random_similarity_params(_seed(seed), math.log(lo), math.log(hi))
    Vu = m.V[_referenced(m)]
    t = t * tr * float(np.linalg.norm(Vu.max(0) - Vu.min(0)))
    out = _same_faces(m, _core.similarity_transform(m.V, R, s, t))
    return (out, R, s, t) if return_transform else out


def reorder(V: MeshLike, F: FacesLike = None, *, seed: int = 0, vertices: bool = True, faces: bool = True,
            return_permutations: bool = False) -> Mesh | tuple[Mesh, IntArray, IntArray]:
    """Random re-ordering of the vertices and/or faces; faces are re-indexed consistently.

    New vertex ``i`` is old vertex ``vertex_perm[i]``; new face ``j`` is old face ``face_perm[j]`` with
    its corners in the same (winding) order. Draw order: vertex permutation, then face permutation.
    With ``return_permutations`` returns ``(mesh, vertex_perm (n,), face_perm (m,))``.
    """
    m = as_mesh(V, F)
    V2, idx, off, vp, fp = _core.permute_mesh(m.V, m.face_indices, m.face_offsets, _seed(seed),
                                              bool(vertices), bool(faces))
    out = Mesh.from_polygons(V2, idx, off, validate=False)
    return (out, vp, fp) if return_permutations else out


# --- noise (eq. 6.3.12) ------------------------------------------------------------------------------

def mean_centroid_distance(V: MeshLike, F: FacesLike = None) -> float:
    """d-bar of eq. 6.3.12: mean distance from the (referenced, if F is given) vertices to their centroid."""
    if F is None and not isinstance(V, Mesh):
        return float(_core.mean_centroid_distance(_as_vertices(V)))
    m = as_mesh(V, F)
    return float(_core.mean_centroid_distance(np.ascontiguousarray(m.V[_referenced(m)])))


def vertex_normals(V: MeshLike, F: FacesLike = None) -> np.ndarray:
    """(n, 3) unit vertex normals: normalized sum of the incident triangles' (b - a) x (c - a)."""
    m = as_mesh(V, F)
    return _core.vertex_normals(m.V, _tri(m))


def noise(V: MeshLike, F: FacesLike = None, *, strength: float, seed: int = 0, kind: str = "uniform") -> Mesh:
    """Additive noise of amplitude ``strength * d-bar`` (d-bar: mean vertex-to-centroid distance).

    kind:
      * ``"uniform"``: ``x' = x + a d-bar``, ``a ~ U[-A, A]`` per coordinate (eq. 6.3.12; the thesis uses
        A = 0.05, 0.10, 0.25, 0.50 %, i.e. ``strength`` 0.0005 ... 0.005);
      * ``"gaussian"``: ``a ~ N(0, A^2)`` per coordinate;
      * ``"normal"``: ``v' = v + a d-bar n``, one ``a ~ U[-A, A]`` per vertex along its unit normal;
      * ``"tangent"``: ``v' = v + A d-bar (u - (u.n) n)``, ``u ~ U[-1, 1]^3``: tangent plane only.

    Unreferenced vertices do not move. MeshError for a negative strength or an unknown kind.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    m = as_mesh(V, F)
    A = _finite(strength, "noise strength")
    if A < 0:
        raise MeshError(f"noise strength must be >= 0 (a fraction: 0.0025 = 0.25 %), got {A}")
    if kind not in NOISE_KINDS:
        raise MeshError(f"unknown noise kind {kind!r} (expected one of {', '.join(NOISE_KINDS)})")
    return _same_faces(m, _core.add_noise(m.V, _tri(m), kind, A, _seed(seed)))


# --- smoothing ---------------------------------------------------------------------------------------

def smooth(V: MeshLike, F: FacesLike = None, *, lam: float = 0.02, iterations: int = 10, weights: str = "uniform",
           fix_boundary: bool = False) -> Mesh:
    """Laplacian smoothing: ``iterations`` simultaneous steps of ``v_i += lam (avg_j v_j - v_i)``.

    ``weights="uniform"``: the plain average of the edge-graph neighbours (polygons as stored; the
    thesis' attack, lambda = 0.02 with 10/30/50 iterations). ``weights="cotangent"``: the
    cotangent-weighted average (weights clamped at 0, recomputed each step, on the triangulation).
    ``lam`` is unitless (the fraction of the way to the average per step); ``lam = 0`` (or 0 iterations)
    is the identity; isolated vertices never move; with ``fix_boundary`` the boundary vertices stay put. MeshError for negative iterations or a non-finite lambda.
    """
    m = as_mesh(V, F)
    lam = _finite(lam, "lambda")
    if isinstance(iterations, bool) or int(iterations) != iterations or iterations < 0:
        raise MeshError(f"smoothing iterations must be an integer >= 0, got {iterations!r}")
    if weights == "uniform":
        V2 = _core.laplacian_smooth(m.V, m.face_indices, m.face_offsets, lam, int(iterations), bool(fix_boundary))
    elif weights == "cotangent":
        V2 = _core.cotangent_smooth(m.V, _tri(m), lam, int(iterations), bool(fix_boundary))
    else:
        raise MeshError(f"unknown smoothing weights {weights!r} (expected uniform or cotangent)")
    return _same_faces(m, V2)


# --- quantization ------------------------------------------------------------------------------------

def quantize(V: MeshLike, F: FacesLike = None, *, bits: int) -> Mesh:
    """Snap every coordinate to the nearest of ``2^bits + 1`` levels ``lo + k (hi - lo) / 2^bits`` of its
    axis (lo, hi: the bounding box of all vertices): error at most half a step. The thesis and the
    Wang et al. benchmark use b = 7..12. MeshError unless 1 <= bits <= 52.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    m = as_mesh(V, F)
    if isinstance(bits, bool) or int(bits) != bits:
        raise MeshError(f"quantization bits must be an integer, got {bits!r}")
    return _same_faces(m, _core.quantize(m.V, int(bits)))


def _t_vector(t, n: int) -> np.ndarray:
    a = np.asarray(t)
    if a.dtype.kind not in "iu":
        raise MeshError(f"t must hold integer bit counts, got dtype {a.dtype}")
    if a.ndim == 0:
        a = np.full(n, int(a))
    if a.shape != (n,):
        raise MeshError(f"t must be a scalar or have shape ({n},), got {a.shape}")
    return np.ascontiguousarray(a, dtype=np.int32)


def dither_bits(V: ArrayLike, t: ArrayLike, words: ArrayLike, word: str = "fixed32") -> np.ndarray:
    """Keep the ``t`` most significant bits of every coordinate word and take the rest from ``words``.

    The deterministic core of the ch. 3-4 dithered quantizer, for analyses that supply their own
    random bits. V (n, 3) float64 (or a Mesh); t scalar or (n,) int (per vertex); words (n, 3) uint64
    (the low ``32 - t`` / ``64 - t`` bits are used). ``word``:

    * ``"fixed32"`` (ch. 4): 32-bit fixed point in the bounding cube (lo = per-axis min, L = largest
      extent), ``q = min(floor((x - lo) / L 2^32), 2^32 - 1)``, decoded as ``lo + L q' / 2^32``;
      keeping t bits leaves an error below ``L 2^-t`` per coordinate;
    * ``"float64"`` (ch. 3, 3.2.1): the IEEE-754 binary64 bit pattern (sign, exponent, mantissa);
      t <= 12 randomizes exponent bits and may produce non-finite values.

    Returns (n, 3) float64.
    """
    Vv = _as_vertices(V)
    W = np.asarray(words)
    if W.shape != Vv.shape or W.dtype.kind not in "iu":
        raise MeshError(f"words must be an (n, 3) integer array like V {Vv.shape}, got {W.shape} {W.dtype}")
    return _core.dither_bits(Vv, _t_vector(t, len(Vv)), np.ascontiguousarray(W.astype(np.uint64, copy=False)), word)


def dithered_quantize(V: ArrayLike, t: ArrayLike, seed: int = 0, word: str = "fixed32") -> np.ndarray:
    """:func:`dither_bits` with random words drawn from ``seed`` (64 bits per coordinate, row by row).

    V (n, 3) or a Mesh; t scalar or (n,); returns (n, 3) float64.
    """
    Vv = _as_vertices(V)
    return _core.dithered_quantize(Vv, _t_vector(t, len(Vv)), _seed(seed), word)


def dither(V: MeshLike, F: FacesLike = None, *, bits: int, seed: int = 0, word: str = "fixed32") -> Mesh:
    """The dithered quantizer as an attack: keep ``bits`` most significant bits per coordinate word,
    randomize the rest (see :func:`dither_bits`). Returns a Mesh with the same faces; MeshError if the
    result has a non-finite coordinate (float64 words with few bits kept).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    m = as_mesh(V, F)
    V2 = dithered_quantize(m.V, int(bits), seed, word)
    return Mesh.from_polygons(V2, m.face_indices, m.face_offsets)


# --- connectivity-changing attacks -------------------------------------------------------------------

def simplify(V: MeshLike, F: FacesLike = None, *, fraction: float) -> Mesh:
    """Edge-collapse simplification down to ``round(fraction * t)`` triangles (CGAL, Garland-Heckbert
    quadrics, optimal placement). Polygons are triangulated first; unreferenced vertices are dropped;
    vertex order is not preserved. The thesis-style strengths keep 90/70/50/25 % of the faces.
    MeshError if fraction is outside (0, 1] or the mesh is too small (target below 4 triangles).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    m = as_mesh(V, F)
    fr = _finite(fraction, "simplification fraction")
    V2, T2 = _core.simplify(m.V, _tri(m), fr)
    return Mesh(V2, T2)


def subdivide(V: MeshLike, F: FacesLike = None, *, scheme: str = "loop", levels: int = 1) -> Mesh:
    """1-to-4 subdivision, ``levels`` times: ``scheme="midpoint"`` (edge midpoints, geometry unchanged)
    or ``"loop"`` (Loop's masks; boundary rules 3/4 v + 1/8 (p + q) and edge midpoints). Polygons are
    triangulated first. Original vertices keep their ids; edge vertices follow (see docs/attacks.md).
    """
    m = as_mesh(V, F)
    if scheme not in ("midpoint", "loop"):
        raise MeshError(f"unknown subdivision scheme {scheme!r} (expected midpoint or loop)")
    if isinstance(levels, bool) or int(levels) != levels or not 0 <= levels <= 6:
        raise MeshError(f"subdivision levels must be an integer in 0..6, got {levels!r}")
    fn = _core.midpoint_subdivide if scheme == "midpoint" else _core.loop_subdivide
    Vc, T = m.V, _tri(m)
    for _ in range(int(levels)):
        Vc, T = fn(Vc, T)
    return Mesh(Vc, T, validate=False)


def crop(V: MeshLike, F: FacesLike = None, *, fraction: float, normal: ArrayLike = (1.0, 0.0, 0.0),
         return_kept: bool = False) -> Mesh | tuple[Mesh, IntArray]:
    """Cut away the slab of relative thickness ``fraction`` at the ``+normal`` end of the mesh.

    ``s = v . n``; faces with every corner at ``s <= max(s) - fraction (max(s) - min(s))`` are kept
    (not cut, so polygons stay polygons) and vertices no kept face uses are removed, order preserved.
    With ``return_kept`` returns ``(mesh, kept (n',) original vertex ids)``. MeshError unless
    0 <= fraction < 1.
    """
    m = as_mesh(V, F)
    V2, idx, off, kept = _core.crop_plane(m.V, m.face_indices, m.face_offsets, _vec3(normal, "normal"),
                                          _finite(fraction, "crop fraction"))
    out = Mesh.from_polygons(V2, idx, off, validate=False)
    return (out, kept) if return_kept else out


# --- storage round trips -----------------------------------------------------------------------------

def float32_cast(V: MeshLike, F: FacesLike = None) -> Mesh:
    """Round every coordinate to the nearest float32 (as Blender, glTF and float PLY/STL store them)."""
    m = as_mesh(V, F)
    return _same_faces(m, m.V.astype(np.float32).astype(np.float64))


_ROUNDTRIP = {
    "obj": dict(decimals=6),                 # fixed notation, 6 decimals, as OBJ exporters write
    "ply": dict(binary=True, float32=True),  # binary PLY with 'property float'
    "stl": dict(binary=True),                # binary STL: float32 triangle soup, welded on reading
}


def file_roundtrip(V: MeshLike, F: FacesLike = None, *, format: str = "obj", decimals: int | None = None) -> Mesh:
    """Write the mesh with :func:`meshmark.write_mesh` and read it back (a storage attack).

    ``"obj"``: fixed notation with ``decimals`` decimals (default 6, as OBJ exporters write: "OBJ at
    6 digits"); ``"ply"``: binary float32; ``"stl"``: binary (float32, triangles only, corners welded
    on equal coordinates: vertex order and unreferenced vertices may change). ``decimals`` (0..17) is
    for OBJ only.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    from ..io import read_mesh, write_mesh

    m = as_mesh(V, F)
    fmt = str(format).lower()
    if fmt not in _ROUNDTRIP:
        raise MeshError(f"unknown round-trip format {format!r} (expected obj, ply or stl)")
    opts = dict(_ROUNDTRIP[fmt])
    if decimals is not None:
        if fmt != "obj":
            raise MeshError(f"round-trip decimals are for obj, not {fmt} (binary float32)")
        if isinstance(decimals, bool) or int(decimals) != decimals or not 0 <= decimals <= 17:
            raise MeshError(f"round-trip decimals must be an integer in 0..17, got {decimals!r}")
        opts["decimals"] = int(decimals)
    with tempfile.TemporaryDirectory(prefix="meshmark-") as d:
        path = os.path.join(d, "mesh." + fmt)
        write_mesh(path, m, **opts)
        return read_mesh(path)
