"""Thesis ch. 3: the normal degradation dis(M, M^t) on the IEEE-754 double pattern, its logistic model
D(t) = C / (1 + e^(-a - b t)) (eq. 3.2.1) and the quantization level for a tolerance (eqs. 3.2.6-3.2.7).

The samples are native (``normal_degradation_sweep.h``: attacks' Float64 dither + metrics'
normal_degradation, the three weightings of eq. 3.2.3 from one set of angles per sample); the fit is
:func:`scipy.optimize.least_squares` with a robust (soft L1) loss.
"""
from __future__ import annotations

import math

import numpy as np

from .. import _core
from .._core import MeshError
from ._common import mesh_arrays, positive, seed_value
from .._typing import ArrayLike, FloatArray
from ..mesh import MeshPair
from typing import Sequence

__all__ = ["WEIGHTINGS", "FIT_LEVELS", "TABLE_3_1", "TABLE_3_2", "degradation_curve", "fit_logistic", "logistic",
           "logistic_level", "degradation_model"]

WEIGHTINGS = ("mean", "area", "dihedral")   # dis^av, dis^ar, dis^an
FIT_LEVELS = (12, 16, 20, 24, 28)           # the five samples of §3.3
# Table 3.1 (a, b, C) and Table 3.2 (t at 1, 5, 10 degrees) of the thesis, for docs and tests
TABLE_3_1 = {
    "fandisk": {"mean": (22.863, -1.168, 1.573), "area": (23.108, -1.184, 1.573), "dihedral": (22.864, -1.168, 1.573)},
    "bunny": {"mean": (22.300, -1.154, 1.570), "area": (22.127, -1.148, 1.570), "dihedral": (22.315, -1.153, 1.570)},
}
TABLE_3_2 = {
    "fandisk": {"mean": (24, 22, 22), "area": (24, 22, 22), "dihedral": (24, 22, 22)},
    "bunny": {"mean": (24, 22, 22), "area": (24, 22, 22), "dihedral": (24, 22, 22)},
}


def _levels(t, lo: int, hi: int, name: str = "t") -> np.ndarray:
    a = np.atleast_1d(np.asarray(t))
    if a.dtype.kind not in "iu":
        if a.dtype.kind == "f" and np.all(a == np.round(a)):
            a = a.astype(np.int64)
        else:
            raise MeshError(f"{name} must hold integers, got {t!r}")
    if a.ndim != 1 or a.size == 0:
        raise MeshError(f"{name} must be a non-empty list of levels")
    if ((a < lo) | (a > hi)).any():
        bad = a[(a < lo) | (a > hi)][0]
        raise MeshError(f"{name} = {int(bad)} is out of range {lo}..{hi}")
    return np.ascontiguousarray(a, dtype=np.int32)


def degradation_curve(mesh: MeshPair, t: ArrayLike = range(65), *, seed: int = 0, repeats: int = 1) -> dict:
    """dis(M, M^t) of eq. 3.2.2, radians, for each level ``t`` (0..64 bits of the double kept, §3.2.1):
    ``{"t": (k,), "mean"/"area"/"dihedral": (k,), "variance": {weighting: (k,)} (over ``repeats``),
    "excluded": (k,) fraction of triangles without a finite normal in M^t}``. Deterministic for a seed;
    sample (t, r) uses its own seed, so a level's value does not depend on the other levels asked for."""
    _, V, T = mesh_arrays(mesh)
    tt = _levels(t, 0, 64)
    if int(repeats) < 1:
        raise MeshError(f"repeats must be >= 1, got {repeats}")
    mean, var, exc = _core.normal_degradation_sweep(V, T, tt, seed_value(seed), int(repeats))
    out = {"t": tt.astype(np.int64), "excluded": exc, "variance": {}}
    for c, w in enumerate(WEIGHTINGS):
        out[w] = mean[:, c]
        out["variance"][w] = var[:, c]
    return out


def logistic(t: ArrayLike, a: float, b: float, C: float) -> FloatArray:
    """D(t) = C / (1 + e^(-a - b t)) (eq. 3.2.1).

    ``t`` (k,) levels (any shape) -> D (k,) radians, same shape."""
    t = np.asarray(t, dtype=np.float64)
    return C / (1 + np.exp(-a - b * t))


def fit_logistic(t: ArrayLike, d: ArrayLike, *, loss: str = "soft_l1", f_scale: float = 0.05) -> dict:
    """Fit eq. 3.2.1 to samples ``d`` (radians) at levels ``t`` by scipy.optimize.least_squares with a
    robust loss (``soft_l1``, residual scale ``f_scale`` radians). Start: C = pi/2, b = -1, a = the
    level where the samples cross C/2. Returns ``{"a", "b", "C", "cost", "success"}``.

    ``t`` and ``d``: (k,) arrays of one length."""
    from scipy.optimize import least_squares
    t = np.asarray(t, dtype=np.float64)
    d = np.asarray(d, dtype=np.float64)
    ok = np.isfinite(d)
    if ok.sum() < 3:
        raise MeshError("the logistic fit needs at least 3 finite samples")
    t, d = t[ok], d[ok]
    order = np.argsort(t)
    t0 = float(np.interp(math.pi / 4, d[order][::-1], t[order][::-1])) if d.max() > math.pi / 4 > d.min() else float(t.mean())
    x0 = np.array([t0, -1.0, math.pi / 2])
    res = least_squares(lambda p: logistic(t, *p) - d, x0, loss=loss, f_scale=f_scale, method="trf",
                        x_scale=np.array([10.0, 1.0, 1.0]))
    a, b, C = (float(v) for v in res.x)
    return {"a": a, "b": b, "C": C, "cost": float(res.cost), "success": bool(res.success)}


def logistic_level(a: float, b: float, C: float, tolerance: float) -> int:
    """t = ceil(-(ln((C - D) / D) + a) / b) with D = ``tolerance`` degrees (eqs. 3.2.6-3.2.7); with
    C = pi/2 and 1 degree this is ceil(-(4.489 + a) / b). MeshError unless 0 < D < C and b < 0."""
    D = math.radians(positive(tolerance, "tolerance"))
    if not D < C:
        raise MeshError(f"tolerance {tolerance} degrees is not below the model's maximum C = {math.degrees(C):.4g} degrees")
    if not b < 0:
        raise MeshError(f"the logistic model has b = {b} >= 0: no level meets a tolerance")
    return int(math.ceil(-(math.log((C - D) / D) + a) / b))


def degradation_model(mesh: MeshPair, tolerances: Sequence[float] = (1.0, 5.0, 10.0), *, seed: int = 0,
                      t: ArrayLike = FIT_LEVELS, repeats: int = 1) -> dict:
    """The ch. 3 analysis of one mesh: the samples at ``t`` (default 12, 16, 20, 24, 28), the logistic
    fit per weighting and the level per tolerance (degrees, as :func:`logistic_level`). Returns
    ``{weighting: {"a", "b", "C", "t": {tol:
    level}, "samples": [...]}, "levels_fitted": [...], "seed": seed}``."""
    tol = [positive(x, "tolerance") for x in tolerances]
    curve = degradation_curve(mesh, t, seed=seed, repeats=repeats)
    out = {"levels_fitted": [int(x) for x in curve["t"]], "seed": int(seed)}
    for w in WEIGHTINGS:
        f = fit_logistic(curve["t"], curve[w])
        f["t"] = {x: logistic_level(f["a"], f["b"], f["C"], x) for x in tol}
        f["samples"] = [float(v) for v in curve[w]]
        out[w] = f
    return out
