"""meshmark.analysis: the distortion analysis of thesis ch. 3-5 (normal and curvature degradation,
quantization levels). The per-element work is native; see ``docs/analysis.md``.

* ch. 4 (:mod:`meshmark.analysis.quantization`): E(theta), bounds, eta, E_mesh, the optimal level
  :func:`quantization_level` and the curvature-adaptive :func:`adaptive_levels`, psi^i, dithering;
* ch. 3 (:mod:`meshmark.analysis.degradation`): dis(M, M^t) on the double pattern, the logistic model
  and its levels;
* ch. 5 (:mod:`meshmark.analysis.curvature`): :func:`gaussian_curvature`, its degradation under
  normal / tangential / random displacement, the linear fit of eq. 5.2.4, the hexagonal pyramid.
"""
from .quantization import (ETA, ALPHA, MU, SIGMA, BOUNDS, TABLE_4_1, expected_normal_angle, table_4_1,
                           monte_carlo_angle, estimate_eta, triangle_heights, mesh_expectation,
                           quantization_level, quantization_details, adaptive_levels, adaptive_details, psi,
                           quantize, quantization_table)
from .curvature import (DIRECTIONS, SWEEP_LEVELS, TABLE_5_1, gaussian_curvature, curvature_degradation, fit_linear,
                        curvature_model, hexagonal_pyramid, pyramid_experiment)
from .degradation import (WEIGHTINGS, FIT_LEVELS, TABLE_3_1, TABLE_3_2, degradation_curve, fit_logistic, logistic,
                          logistic_level, degradation_model)

__all__ = [
    "ETA", "ALPHA", "MU", "SIGMA", "BOUNDS", "TABLE_4_1", "expected_normal_angle", "table_4_1",
    "monte_carlo_angle", "estimate_eta", "triangle_heights", "mesh_expectation", "quantization_level",
    "quantization_details", "adaptive_levels", "adaptive_details", "psi", "quantize", "quantization_table",
    "DIRECTIONS", "SWEEP_LEVELS", "TABLE_5_1", "gaussian_curvature", "curvature_degradation", "fit_linear",
    "curvature_model", "hexagonal_pyramid", "pyramid_experiment",
    "WEIGHTINGS", "FIT_LEVELS", "TABLE_3_1", "TABLE_3_2", "degradation_curve", "fit_logistic", "logistic",
    "logistic_level", "degradation_model",
]
