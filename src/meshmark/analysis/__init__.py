"""meshmark.analysis: the distortion analysis of thesis ch. 3-5 (normal and curvature degradation,
quantization levels). The per-element work is native; see ``docs/analysis.md``.

* ch. 4 (:mod:`meshmark.analysis.quantization`): E(theta), bounds, eta, E_mesh, the optimal level
  :func:`quantization_level` and the curvature-adaptive :func:`adaptive_levels`, psi^i, dithering;
* ch. 5 (:mod:`meshmark.analysis.curvature`): :func:`gaussian_curvature`.
"""
from .quantization import (ETA, ALPHA, MU, SIGMA, BOUNDS, TABLE_4_1, expected_normal_angle, table_4_1,
                           monte_carlo_angle, estimate_eta, triangle_heights, mesh_expectation,
                           quantization_level, quantization_details, adaptive_levels, adaptive_details, psi,
                           quantize, quantization_table)
from .curvature import gaussian_curvature

__all__ = [
    "ETA", "ALPHA", "MU", "SIGMA", "BOUNDS", "TABLE_4_1", "expected_normal_angle", "table_4_1",
    "monte_carlo_angle", "estimate_eta", "triangle_heights", "mesh_expectation", "quantization_level",
    "quantization_details", "adaptive_levels", "adaptive_details", "psi", "quantize", "quantization_table",
    "gaussian_curvature",
]
