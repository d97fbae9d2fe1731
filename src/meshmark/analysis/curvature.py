"""Thesis ch. 5: discrete Gaussian curvature and its degradation under vertex displacement."""
from __future__ import annotations

import numpy as np

from .. import _core
from .._core import MeshError
from ._common import mesh_arrays, positive, seed_value
from .degradation import _levels
from .._typing import ArrayLike, FloatArray, IntArray
from ..mesh import MeshPair
from typing import Sequence

__all__ = ["DIRECTIONS", "SWEEP_LEVELS", "TABLE_5_1", "gaussian_curvature", "curvature_degradation", "fit_linear",
           "curvature_model", "hexagonal_pyramid", "pyramid_experiment"]


def gaussian_curvature(mesh: MeshPair) -> dict:
    """Discrete Gaussian curvature (eq. 5.1.1, the angle deficit), radians: ``{"kappa" (n,),
    "interior" (n,) bool, "boundary" (n,) bool}``. Interior vertices: 2 pi - sum of incident angles;
    boundary vertices (on an edge with one triangle): pi - sum (the boundary angle deficit, 0 on a flat
    straight border); vertices on a non-manifold edge keep 2 pi - sum but are not interior;
    unreferenced vertices 0 and not interior."""
    _, V, T = mesh_arrays(mesh)
    k, interior, boundary = _core.gaussian_curvature(V, T)
    return {"kappa": k, "interior": interior.astype(bool), "boundary": boundary.astype(bool)}


DIRECTIONS = ("normal", "tangential", "random")
SWEEP_LEVELS = tuple(range(1, 21))   # 20 levels; the fit of eq. 5.2.4 uses t >= 12
TABLE_5_1 = {"bunny": (34835, -1.0, 5.05), "dragon": (19851, -1.0, 5.46), "brain": (18375, -1.0, 1.85),
             "chair": (3413, -1.0, 7.84)}   # thesis: #vertices, slope a, intercept b of eq. 5.2.4


def _mask(x, n: int, name: str) -> np.ndarray:
    a = np.asarray(x)
    if a.dtype == bool and a.shape == (n,):
        return a.astype(np.uint8)
    a = np.asarray(x, dtype=np.int64).ravel()
    if ((a < 0) | (a >= n)).any():
        raise MeshError(f"{name}: vertex index out of range 0..{n - 1}")
    m = np.zeros(n, np.uint8)
    m[a] = 1
    return m


def curvature_degradation(mesh: MeshPair, t: ArrayLike = SWEEP_LEVELS, direction: str = "normal", *,
                          seed: int = 0, repeats: int = 1,
                          scale: float | None = None, moved: ArrayLike | None = None,
                          measured: ArrayLike | None = None) -> np.ndarray:
    """kappa_dif(t) of §5.2: the mean |kappa' - kappa| (radians) over the measured vertices after every
    moved vertex is displaced by s * scale along its ``direction`` (``normal``: the mean of the unit
    normals of its triangles, as §5.2; ``tangential``: a random unit direction of its tangent plane;
    ``random``: a random unit direction), s ~ U[-2^(1-t), 2^(1-t)] so that E|s| = 2^-t, averaged over
    ``repeats``. ``scale``: model units per unit strength, default the largest bounding-box extent L
    (the bounding cube of ch. 4), so t means the same relative displacement on every mesh. ``moved``
    and ``measured``: vertex indices or (n,) bool masks; defaults: every referenced vertex is moved,
    every interior vertex measured (boundary vertices have a different curvature definition).
    Returns (k,) float64."""
    m, V, T = mesh_arrays(mesh)
    if direction not in DIRECTIONS:
        raise MeshError(f"direction must be one of {', '.join(DIRECTIONS)}, got {direction!r}")
    tt = _levels(t, 0, 1074)
    n = m.n_vertices
    g = None
    if moved is None:
        mv = m.referenced().astype(np.uint8)
    else:
        mv = _mask(moved, n, "moved")
    if measured is None:
        g = gaussian_curvature((V, T))
        ms = g["interior"].astype(np.uint8)
    else:
        ms = _mask(measured, n, "measured")
    if scale is None:
        scale = float(np.ptp(V, axis=0).max())
    if int(repeats) < 1:
        raise MeshError(f"repeats must be >= 1, got {repeats}")
    return _core.curvature_degradation(V, T, tt, direction, mv, ms, positive(scale, "scale"), int(repeats),
                                       seed_value(seed))


def fit_linear(t: ArrayLike, kappa_dif: ArrayLike, *, t_min: int = 12) -> dict:
    """The linear model of eq. 5.2.4 as the thesis reports it (Table 5.1: slope -1): least squares
    log2 kappa_dif = a t + b over the levels t >= ``t_min`` (numpy.polyfit, degree 1). Returns
    ``{"a", "b", "r2", "n"}``.

    ``t``, ``kappa_dif``: (k,) arrays of one length (levels, curvature changes)."""
    t = np.asarray(t, dtype=np.float64)
    y = np.log2(np.asarray(kappa_dif, dtype=np.float64))
    ok = (t >= t_min) & np.isfinite(y)
    if ok.sum() < 2:
        raise MeshError(f"the linear fit needs at least 2 levels t >= {t_min} with kappa_dif > 0")
    a, b = np.polyfit(t[ok], y[ok], 1)
    res = y[ok] - (a * t[ok] + b)
    ss = float(((y[ok] - y[ok].mean()) ** 2).sum())
    return {"a": float(a), "b": float(b), "r2": 1 - float((res ** 2).sum()) / ss if ss > 0 else 1.0, "n": int(ok.sum())}


def curvature_model(mesh: MeshPair, t: ArrayLike = SWEEP_LEVELS, *, seed: int = 0, repeats: int = 1,
                    t_min: int = 12,
                    directions: Sequence[str] = DIRECTIONS) -> dict:
    """The §5.2 experiment on one mesh: kappa_dif(t) per direction and the eq. 5.2.4 fit over
    t >= t_min: ``{direction: {"a", "b", "r2", "n", "kappa_dif": [...]}, "t": [...], "scale": L,
    "n_interior": int}``.

    ``mesh``: a Mesh or ``(V (n, 3), F (m, 3))``; ``t`` the (k,) levels
    (displacement s ~ U[-2^(1-t), 2^(1-t)] x L, as in :func:`curvature_degradation`)."""
    m, V, T = mesh_arrays(mesh)
    tt = _levels(t, 0, 1074)
    g = gaussian_curvature((V, T))
    out = {"t": [int(x) for x in tt], "scale": float(np.ptp(V, axis=0).max()), "n_interior": int(g["interior"].sum())}
    for d in directions:
        k = curvature_degradation((V, T), tt, d, seed=seed, repeats=repeats, measured=g["interior"])
        f = fit_linear(tt, k, t_min=t_min)
        f["kappa_dif"] = [float(x) for x in k]
        out[d] = f
    return out


def hexagonal_pyramid(height: float = 1.0, radius: float = 1.0) -> tuple[FloatArray, IntArray]:
    """The regular right hexagonal pyramid of Fig. 5.5: apex (0, 0, height) = vertex 0, base hexagon of
    circumradius ``radius`` in z = 0 (vertices 1..6), the 6 side triangles (no base, so only the apex
    is interior). ``height`` and ``radius`` in mesh units. Returns (V (7, 3) float64, F (6, 3) int)."""
    ang = np.arange(6) * np.pi / 3
    V = np.r_[[[0.0, 0.0, float(height)]], np.c_[radius * np.cos(ang), radius * np.sin(ang), np.zeros(6)]]
    F = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)])
    return V, F


def pyramid_experiment(t: ArrayLike = tuple(range(0, 41)), *, repeats: int = 2000, seed: int = 0, t_min: int = 2,
                       t_max: int = 20) -> dict:
    """Fig. 5.5: noise of mean strength 2^-t (model units: height = radius = 1) added to the apex only,
    in the normal (the axis) and in a tangential direction; the mean |kappa' - kappa| at the apex over
    ``repeats`` draws, and the slopes of log2 kappa_dif over t_min <= t <= t_max: the tangential
    change is O(eps^2) and reaches the precision of the angle sums (~2^-50) near t = 24, where the
    curve levels off as the thesis notes; the window stays below that. Returns ``{"t", "normal", "tangential",
    "fit": {direction: {"a", "b", "r2", "n"}}, "slope_ratio": a_tangential / a_normal}``.

    ``t``: (k,) integer levels; ``normal`` and ``tangential`` are (k,) lists of radians."""
    V, F = hexagonal_pyramid()
    out = {"t": [int(x) for x in t], "fit": {}}
    for d in ("normal", "tangential"):
        k = curvature_degradation((V, F), t, d, seed=seed, repeats=repeats, scale=1.0, moved=[0], measured=[0])
        out[d] = [float(x) for x in k]
        tt = np.asarray(out["t"])
        sel = tt <= t_max
        out["fit"][d] = fit_linear(tt[sel], k[sel], t_min=t_min)
    out["slope_ratio"] = out["fit"]["tangential"]["a"] / out["fit"]["normal"]["a"]
    return out
