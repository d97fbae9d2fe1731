"""Thesis ch. 5: discrete Gaussian curvature and its degradation under vertex displacement."""
from __future__ import annotations

import numpy as np

from .. import _core
from ._common import mesh_arrays

__all__ = ["gaussian_curvature"]


def gaussian_curvature(mesh) -> dict:
    """Discrete Gaussian curvature (eq. 5.1.1, the angle deficit), radians: ``{"kappa" (n,),
    "interior" (n,) bool, "boundary" (n,) bool}``. Interior vertices: 2 pi - sum of incident angles;
    boundary vertices (on an edge with one triangle): pi - sum (the boundary angle deficit, 0 on a flat
    straight border); vertices on a non-manifold edge keep 2 pi - sum but are not interior;
    unreferenced vertices 0 and not interior."""
    _, V, T = mesh_arrays(mesh)
    k, interior, boundary = _core.gaussian_curvature(V, T)
    return {"kappa": k, "interior": interior.astype(bool), "boundary": boundary.astype(bool)}
