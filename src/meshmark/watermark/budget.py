"""The distortion budget of issued copies (docs/tracing.md, "Distortion budget").

Every copy :func:`.tracing.issue` makes must stay invisible: vertex RMSE <= 1e-4 and symmetric
Hausdorff distance <= 5e-4 of the bounding-box diagonal, mean normal change <= 0.25 degrees
(:data:`BUDGET`). A copy is the original moved by the keyed informed pattern and the blind codeword on
top; on smooth, finely meshed assets both fit with room to spare, on CAD, thin and coarse meshes the
blind Laplacian mark alone can exceed the budget several times (flat regions: a vertex moved to
another histogram bin leaves its plane).

:func:`measure` gives a copy's three figures as shares of the budget (1 = at the limit). The vertex
RMSE and the normal change are exact; the Hausdorff share is first bounded by the largest vertex
displacement (for two meshes with the same faces each point of a triangle moves by a convex
combination of its corners' displacements) and, only when that bound is not within
:data:`MARGIN`, computed (the upper bound of :func:`meshmark.metrics.hausdorff_distance`, both
ways: tangential moves on flat parts, which the displacement counts, do not change the surface).

:data:`LADDER` is what :func:`.tracing.issue` tries, in order, for a new asset whose trial copies do
not fit: a larger ``n_robust`` (eq. 7.2.16: the losing bin of a pair keeps more of its vertices, so
fewer move; Laplacian only), then a weaker pattern. The first step whose trial copies all fit
:data:`MARGIN` of the budget is kept; if none does, the first within the budget itself; if none is,
the automatic parameters (their blind mark is the most robust; a weaker one would not make the
copies invisible). The gentlest step is tried right after the automatic one: if every trial copy there
is beyond :data:`HOPELESS` times the budget, no step can fit, and the automatic parameters are kept
without walking the ladder or remaking copies (``"remake": false``, ``"gentlest_share"``). The
asset's setup records the outcome: ``setup['budget']`` = ``{"fits": every trial copy within the budget,
"worst_share": the trial copies' largest share, "n_robust", "pattern_scale", "trials"}``. A larger
n_robust makes the blind codeword less robust (it reads through less noise without the original);
the informed pattern, weakened only as a last resort, carries the evidence against a leaker who
tries.
"""
from __future__ import annotations

import math

import numpy as np

from .. import _core

BUDGET = {"rmse": 1e-4, "hausdorff": 5e-4, "normal_deg": 0.25}
MARGIN = 0.85       # trial copies must fit this share of the budget (copies differ by codeword and pattern)
TRIALS = 4          # trial copies per step of the ladder
# (n_robust at least, pattern RMSE scale): tried in order after the automatic parameters; n_robust never
# beyond n_thr - 1 (eq. 7.2.16 keeps a margin of one vertex: with none, a copy's slightly different
# histogram range flips half its bits against the shared side information)
# every trial copy of the gentlest step (LADDER[-1], tried second) beyond this share of the budget: the other
# steps move vertices more, so none is tried and no copy is remade (tube meshes: vtk_trumpet). The best
# trial, not the worst: copies' shares vary with the codeword (fandisk: 0.84 to 2.44 at the gentlest step)
HOPELESS = 1.5
LADDER = ((None, 1.0), (3, 1.0), (5, 1.0), (8, 1.0), (12, 1.0), (15, 1.0), (15, 0.8), (15, 0.6), (15, 0.45),
          (15, 0.3))


def measure(V0: np.ndarray, T: np.ndarray, V: np.ndarray, diag: float) -> dict:
    """A copy's distortion as shares of :data:`BUDGET`: ``{"rmse", "hausdorff", "normal_deg"}`` (1 = at
    the limit), from the original's vertices V0 (n, 3), its triangles T (t, 3) int32 and diagonal and
    the copy's vertices V (n, 3); only referenced vertices count."""
    ref = np.zeros(len(V0), bool)
    ref[T.ravel()] = True
    d = np.linalg.norm((V - V0)[ref], axis=1)
    rmse = math.sqrt(float((d * d).mean())) if d.size else 0.0
    V = np.ascontiguousarray(V, np.float64)
    normal = math.degrees(_core.normal_degradation(V0, V, T, "mean", 0.0, 3.5)[0])
    haus = float(d.max(initial=0.0)) / diag / BUDGET["hausdorff"]
    if haus > MARGIN:  # the bound does not show the copy within: the symmetric Hausdorff distance itself
        from ..metrics import hausdorff_distance
        haus = max(hausdorff_distance((V0, T), (V, T))["upper"],
                   hausdorff_distance((V, T), (V0, T))["upper"]) / diag / BUDGET["hausdorff"]
    return {"rmse": rmse / diag / BUDGET["rmse"], "hausdorff": haus, "normal_deg": normal / BUDGET["normal_deg"]}


def worst(share: dict) -> float:
    """The largest of a copy's shares (<= 1: within the budget)."""
    return max(share.values())


# a copy beyond the budget is remade with a larger n_robust (never beyond n_thr - 1), then its pattern scaled so
COPY_N_ROBUST = (5, 8, 12, 15)
COPY_SCALES = (0.6, 0.35)


class Reference:
    """The original's vertices, triangles (int32) and diagonal over referenced vertices, for
    :func:`measure` (informed.Original offers the same attributes)."""

    def __init__(self, mesh):
        self.V = np.ascontiguousarray(mesh.V, np.float64)
        self.T = np.ascontiguousarray(mesh.triangles, np.int32)
        P = self.V[np.unique(self.T)]
        self.diag = float(np.linalg.norm(P.max(0) - P.min(0))) if len(P) else 1.0


def summary(shares) -> dict:
    """The distortion of issued copies from their largest shares (:func:`worst` of each)."""
    shares = [float(x) for x in shares]
    return {"limits": dict(BUDGET), "n_copies": len(shares), "copies_beyond": sum(x > 1.0 for x in shares),
            "largest_share": round(max(shares, default=0.0), 4)}
