"""Thesis ch. 4: the expected normal change under uniform noise, its bounds, and the optimal and
curvature-adaptive dithered-quantization levels (native core: ``quantization_level.h``,
``normal_angle_expectation.h``; see ``docs/analysis.md``).

* :func:`expected_normal_angle` — E(theta) of eq. 4.1.7 (+ 4.1.8 for l > h) as a function of r = l/h;
  :func:`table_4_1` its distance to the tangent r/2; :func:`monte_carlo_angle` the same expectation by
  simulation; :func:`estimate_eta` the constant eta of eq. 4.1.16 (thesis: 0.608).
* :func:`triangle_heights`, :func:`mesh_expectation` — E_min, E_max, E_appr per triangle averaged over
  the mesh, E_mesh of eq. 4.2.18.
* :func:`quantization_level` — the level i of eqs. 4.3.19-4.3.21 for 32-bit fixed point in the
  bounding cube; :func:`adaptive_levels` — per-vertex levels of eqs. 4.3.23-4.3.25.
* :func:`psi` — the measured degradation psi^i of eq. 4.3.22 after dithering; :func:`quantize` — the
  dithered mesh; :func:`quantization_table` — Tables 4.2 and 4.3 for one mesh.

Units: tolerances in degrees at the API (the thesis' epsilon), radians inside; l and heights in model
units; levels are bits kept of the 32-bit fixed-point word.
"""
from __future__ import annotations

import math

import numpy as np

from .. import _core
from .._core import MeshError
from ..mesh import Mesh, MeshPair
from ._common import mesh_arrays, positive, seed_value
from .._typing import ArrayLike, FloatArray
from typing import Sequence

__all__ = [
    "ETA", "ALPHA", "MU", "SIGMA", "BOUNDS", "expected_normal_angle", "table_4_1", "monte_carlo_angle",
    "estimate_eta", "triangle_heights", "mesh_expectation", "quantization_level", "quantization_details",
    "adaptive_levels", "adaptive_details", "psi", "quantize", "quantization_table", "TABLE_4_1",
]

ETA = 0.608          # eq. 4.1.16, the thesis' Monte Carlo value (estimate_eta reruns it)
ALPHA, MU, SIGMA = 0.7979, 0.0, 0.5   # eq. 4.3.24 constants of Fig. 4.7 (eps0 is the tolerance)
BOUNDS = ("min", "appr", "max", "exact")
TABLE_4_1 = {0.1: 0.0001, 0.2: 0.0006, 0.3: 0.0021, 0.4: 0.0049, 0.5: 0.0092}  # thesis E(theta) - l/2h


def expected_normal_angle(r: ArrayLike) -> float | FloatArray:
    """E(theta) of eqs. 4.1.7/4.1.8, radians, for r = l/h (scalar or array, r >= 0): the expected angle
    between a triangle's normal and its normal after noise uniform in a cube of edge 2l (one face
    parallel to the triangle) is added to the vertex of height h. E'(0) = 1/2; pi/2 as r -> inf.

    Shapes: a scalar gives a float, an array of shape (k,) (any shape) gives the same shape."""
    a = np.asarray(r, dtype=np.float64)
    out = _core.expected_normal_angle(np.ascontiguousarray(a.ravel()))
    return float(out[0]) if a.ndim == 0 else out.reshape(a.shape)


def table_4_1(ratios: Sequence[float] = (0.1, 0.2, 0.3, 0.4, 0.5)) -> dict:
    """Table 4.1: {l/h: E(theta) - l/2h}."""
    return {float(r): float(expected_normal_angle(r) - r / 2) for r in ratios}


def monte_carlo_angle(r: float, n: int = 10 ** 6, seed: int = 0) -> tuple[float, float]:
    """E(theta) by simulation for A = (0,0,0), B = (1,0,0), C = (0,1,0) and noise U[-r, r]^3 on C
    (h = 1, l = r): ``(mean, standard error)`` in radians over ``n`` samples."""
    r = float(r)
    if not (r >= 0 and math.isfinite(r)):
        raise MeshError(f"r must be a finite number >= 0, got {r}")
    P = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    mean, se, _ = _core.normal_noise_monte_carlo(P, np.array([0, 0, 1], np.int32), r, int(n), seed_value(seed))
    return mean, se


def estimate_eta(n: int = 10 ** 6, l: float = 2.0 ** -10, seed: int = 0) -> tuple[float, float]:
    """eta of eq. 4.1.16 as the thesis estimated it: noise U[-l, l]^3 on the three vertices of an
    equilateral triangle of side 1 (in the xy-plane), the mean normal change divided by
    E(theta_1) + E(theta_2) + E(theta_3) = 3 E(l / h), h = sqrt(3)/2. Returns ``(eta, standard error)``.
    ``l`` is in the units of that triangle (side 1: a fraction of its side); eta is unitless."""
    l = positive(l, "l")
    P = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, math.sqrt(3) / 2, 0]])
    mean, se, _ = _core.normal_noise_monte_carlo(P, np.array([1, 1, 1], np.int32), l, int(n), seed_value(seed))
    den = 3 * expected_normal_angle(l / (math.sqrt(3) / 2))
    return mean / den, se / den


def triangle_heights(mesh: MeshPair) -> tuple[np.ndarray, np.ndarray]:
    """``(h (t, 3) sorted heights h1 <= h2 <= h3 in model units, usable (t,) bool)``; zero-area
    triangles are not usable (their rows are 0)."""
    _, V, T = mesh_arrays(mesh)
    h, ok = _core.triangle_heights(V, T)
    return h, ok.astype(bool)


def _bound(bound: str) -> tuple[str, str]:
    if bound not in BOUNDS:
        raise MeshError(f"bound must be one of {', '.join(BOUNDS)}, got {bound!r}")
    return ("appr", "exact") if bound == "exact" else (bound, "auto")


def mesh_expectation(mesh: MeshPair, l: float, bound: str = "appr", *, exact: bool = False, eta: float = ETA) -> float:
    """E_mesh(theta) of eq. 4.2.18, radians: the mean over the usable triangles of E_min (eq. 4.1.10),
    E_max = 2 E_min (4.1.15) or E_appr = eta sum_k E(theta_k) (4.1.16) for noise of half-width ``l``
    (model units, scalar or array). ``exact``: E(theta) of eq. 4.1.7, else its tangent l/2h (4.1.9)."""
    if bound not in ("min", "appr", "max"):
        raise MeshError(f"bound must be min, appr or max, got {bound!r}")
    _, V, T = mesh_arrays(mesh)
    a = np.asarray(l, dtype=np.float64)
    if not (np.isfinite(a).all() and (a >= 0).all()):
        raise MeshError("l must be finite and >= 0")
    out = _core.mesh_normal_expectation(V, T, np.ascontiguousarray(a.ravel()), bound, bool(exact), positive(eta, "eta"))
    return float(out[0]) if a.ndim == 0 else out.reshape(a.shape)


def quantization_details(mesh: MeshPair, tolerance: float = 1.0, bound: str = "appr", *, eta: float = ETA,
                         formula: str | None = None, switch_tol: float = 0.1) -> dict:
    """:func:`quantization_level` with its evidence: ``level`` (0..32), ``level_unclamped``,
    ``level_linear`` (closed form), ``used_exact``, ``e_linear`` / ``e_exact`` (E_mesh at the closed-form
    level, radians), ``e_level``, ``cube`` (L), ``n_triangles``; ``formula`` overrides the choice
    (``auto``, ``linear``, ``exact``).

    ``mesh``: a Mesh or ``(V (n, 3), F (m, 3))``; ``tolerance`` in degrees."""
    b, f = _bound(bound)
    if formula is not None:
        f = formula
    _, V, T = mesh_arrays(mesh)
    eps = math.radians(positive(tolerance, "tolerance"))
    d = dict(_core.quantization_level(V, T, eps, b, f, positive(eta, "eta"), float(switch_tol)))
    d.update(bound=bound, tolerance=float(tolerance), formula=f)
    return d


def quantization_level(mesh: MeshPair, tolerance: float = 1.0, bound: str = "appr", *, eta: float = ETA) -> int:
    """The optimal dithered-quantization level i (eqs. 4.3.19-4.3.21): the fewest most significant bits
    of the 32-bit fixed-point coordinate (bounding cube, as :func:`meshmark.attacks.dither`) to keep so
    that the expected mean normal change E_mesh stays within ``tolerance`` degrees.

    ``bound``: ``min`` (eq. 4.3.20), ``appr`` (eq. 4.3.21, eta = 0.608), ``max`` (E_max = 2 E_min) use
    the linear E(theta) ~ l/2h unless it misestimates E_mesh at its level by more than 10 % (skinny
    triangles, the MPII case of Fig. 4.4), where the exact eq. 4.1.7 decides; ``exact`` is E_appr with
    the exact E(theta) throughout. ``mesh``: a Mesh or (V, F). Returns an int in 0..32.
    MeshError if tolerance <= 0 or the mesh has no usable (non-zero area) triangle.
    """
    b, f = _bound(bound)
    _, V, T = mesh_arrays(mesh)
    eps = math.radians(positive(tolerance, "tolerance"))
    eta = positive(eta, "eta")
    # one pass without the exact E_mesh where it cannot change the level (quantization_level.h); the
    # same integer as quantization_details (tests/test_stego.py::test_fast_levels_equal_general_ones)
    lv = _core.quantization_level_only(V, T, eps, b, f, eta, 0.1)
    if lv is not None:
        return int(lv)
    return int(quantization_details(mesh, tolerance, bound, eta=eta)["level"])


def adaptive_details(mesh: MeshPair, tolerance: float = 1.0, *, alpha: float = ALPHA, mu: float = MU,
                     sigma: float = SIGMA,
                     eta: float = ETA) -> dict:
    """:func:`adaptive_levels` with ``levels`` (n,), ``triangle_levels`` (t,), ``triangle_tolerance``
    (t,) radians and ``kappa`` (n,) (the curvature used, eq. 4.3.23)."""
    from .curvature import gaussian_curvature
    _, V, T = mesh_arrays(mesh)
    eps0 = math.radians(positive(tolerance, "tolerance"))
    kappa = gaussian_curvature((V, T))["kappa"]
    lv, lt, et = _core.adaptive_levels(V, T, kappa, eps0, float(alpha), float(mu), positive(sigma, "sigma"),
                                       positive(eta, "eta"))
    return {"levels": lv.astype(np.int64), "triangle_levels": lt, "triangle_tolerance": et, "kappa": kappa}


def adaptive_levels(mesh: MeshPair, tolerance: float = 1.0, *, alpha: float = ALPHA, mu: float = MU,
                    sigma: float = SIGMA,
                    eta: float = ETA) -> np.ndarray:
    """Curvature-adaptive per-vertex levels (eqs. 4.3.23-4.3.25): each triangle j gets the tolerance
    eps_j = min over its vertices of alpha - phi(kappa_n; alpha, mu, sigma) + eps0 (phi: Gaussian of
    peak alpha; kappa_n the angle deficit of eq. 4.3.23, boundary vertices pi - angle sum), its level is
    the fewest bits with E_appr,j <= eps_j (exact E(theta)), and a vertex takes the largest level of its
    triangles. ``tolerance`` is eps0 in degrees (the thesis used 0.0017 rad ~ 0.1 deg); alpha = 0.7979,
    mu = 0, sigma = 0.5 (Fig. 4.7). Returns (n,) int64 in 0..32 (0 for unreferenced vertices, 32 for
    vertices with only zero-area triangles)."""
    if float(alpha) == 0.0:  # eps_j = eps0 for every triangle: no curvature needed (quantization_level.h)
        _, V, T = mesh_arrays(mesh)
        eps0 = math.radians(positive(tolerance, "tolerance"))
        positive(sigma, "sigma")
        if not math.isfinite(float(mu)):
            raise MeshError("alpha and mu must be finite")
        lv = _core.uniform_adaptive_levels(V, T, eps0, positive(eta, "eta"))
        if lv is not None:
            return lv.astype(np.int64)
    return adaptive_details(mesh, tolerance, alpha=alpha, mu=mu, sigma=sigma, eta=eta)["levels"]


def _levels_vector(levels, n: int) -> np.ndarray:
    a = np.asarray(levels)
    if a.dtype.kind not in "iu" and not (a.dtype.kind == "f" and np.all(a == np.round(a))):
        raise MeshError("levels must be integers")
    a = a.astype(np.int64)
    if a.ndim == 0:
        a = np.full(n, int(a))
    if a.shape != (n,):
        raise MeshError(f"levels must be a scalar or have shape ({n},), got {a.shape}")
    if ((a < 0) | (a > 32)).any():
        raise MeshError(f"levels must lie in 0..32, got {int(a.min())}..{int(a.max())}")
    return a.astype(np.int32)


def quantize(mesh: MeshPair, tolerance: float | None = None, *, levels: ArrayLike | int | None = None,
             adaptive: bool = False, bound: str = "appr",
             seed: int = 0) -> Mesh:
    """The dithered mesh (32-bit fixed point in the bounding cube, low bits random; attacks'
    ``dithered_quantize``) at ``levels`` (scalar or (n,)) or, if None, at the level for ``tolerance``
    degrees: :func:`quantization_level` with ``bound``, or :func:`adaptive_levels` if ``adaptive``.
    The faces are kept as stored; the input is not modified."""
    from ..attacks import dithered_quantize
    m, V, T = mesh_arrays(mesh)
    if levels is None:
        if tolerance is None:
            raise MeshError("give a tolerance or levels")
        levels = adaptive_levels(m, tolerance) if adaptive else quantization_level(m, tolerance, bound)
    t = _levels_vector(levels, m.n_vertices)
    V2 = dithered_quantize(V, t, seed_value(seed), "fixed32")
    return Mesh.from_polygons(V2, m.face_indices, m.face_offsets, validate=False)


def psi(mesh: MeshPair, levels: ArrayLike | int, *, seed: int = 0, repeats: int = 1) -> float:
    """psi^i of eq. 4.3.22 in degrees: the mean angle between the triangle normals of ``mesh`` and of
    the mesh dithered at ``levels`` (scalar or (n,)), averaged over ``repeats`` dithers (seeds seed,
    seed + 1, ...). Zero-area triangles are excluded (metrics.normal_degradation)."""
    from ..metrics import normal_degradation
    m, V, T = mesh_arrays(mesh)
    t = _levels_vector(levels, m.n_vertices)
    from ..attacks import dithered_quantize
    s = seed_value(seed)
    vals = [normal_degradation(V, dithered_quantize(V, t, s + k, "fixed32"), T, weighting="mean", degrees=True)
            for k in range(int(repeats))]
    return float(np.mean(vals))


def quantization_table(mesh: MeshPair, tolerances: Sequence[float] = (0.1, 1.0, 10.0),
                       bounds: Sequence[str] = ("min", "appr", "max", "exact"), *,
                       adaptive: bool = False, seed: int = 0) -> dict:
    """Tables 4.2 and 4.3 for one mesh: ``{"n_triangles", "cube", "levels": {bound: {tol: i}},
    "psi": {bound: {tol: psi^i in degrees}}, "details": {bound: {tol: quantization_details}}}``, and
    with ``adaptive`` also ``"adaptive": {tol: {"mean_level", "min", "max", "total_bits",
    "global_total_bits", "psi"}}`` (total bits kept = 3 sum_n i_n; the global level for comparison is
    the ``appr`` one).

    ``mesh``: a Mesh or ``(V (n, 3), F (m, 3))``; ``tolerances`` in degrees."""
    m, V, T = mesh_arrays(mesh)
    out = {"levels": {}, "psi": {}, "details": {}}
    for b in bounds:
        out["levels"][b], out["psi"][b], out["details"][b] = {}, {}, {}
        for tol in tolerances:
            d = quantization_details(m, tol, b)
            out["levels"][b][tol] = int(d["level"])
            out["details"][b][tol] = d
            out["psi"][b][tol] = psi(m, d["level"], seed=seed)
    d0 = next(iter(next(iter(out["details"].values())).values()))
    out["n_triangles"], out["cube"] = int(d0["n_triangles"]), float(d0["cube"])
    if adaptive:
        out["adaptive"] = {}
        used = m.referenced().astype(bool)
        for tol in tolerances:
            lv = adaptive_levels(m, tol)
            g = quantization_level(m, tol, "appr")
            out["adaptive"][tol] = {
                "mean_level": float(lv[used].mean()), "min": int(lv[used].min()), "max": int(lv[used].max()),
                "total_bits": int(3 * lv[used].sum()), "global_level": g,
                "global_total_bits": int(3 * g * used.sum()), "psi": psi(m, lv, seed=seed)}
    return out
