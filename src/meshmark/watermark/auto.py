"""Automatic parameters (``params="auto"``, the default of embed, the CLI and the add-on).

Given the mesh and the payload, each method offers a *ladder* of parameter sets, most robust carrier
first (:data:`LADDERS`); the first rung is the published default (``params="thesis"``). The choice is
the first rung on which the payload fits (C >= 1.5 (k + 20) carriers for k payload bits, the
punctured rate 2/3 of :mod:`.coding`); if none fits, the rung with the largest capacity (embedding
then refuses, naming the capacity).

Why "first fit" and not "most carriers": the robustness of a Laplacian carrier falls steeply with
finer bins (docs/coding.md, "Choosing the parameters": on the Bunny, uniform noise of 5e-5 leaves CDR
0.97 at K = ceil(N/70), n_thr = 46 and 0.68 at K = ceil(N/35), n_thr = 23), far more than the code
gains from the extra carriers, so the coarsest bins that take the payload are the most robust choice.

Parameters given explicitly (``K=...``) are kept on every rung. The choice depends only on the mesh,
the payload length and the given parameters (deterministic) and is recorded in the keyfile
(``choice``). A rung costs one histogram pass on lengths computed once (cached on the mesh), and
only rungs before the chosen one are evaluated, so the choice adds little to an embedding
(bench/laplacian_bench.py prints the ratio).

Laplacian ladder: vertices per bin N_c = 70 (§7.4: K = ceil(N/70), n_thr = 46, n_robust = 5), then
N_c = 50, 35, 25, 18, 12 with n_thr = 33, 23, 16, 12, 8 (n_thr / N_c as in the thesis), and last
resorts for meshes whose Laplacian lengths have a long tail (most bins empty): N_c = 8, 6, 4, 3 with
n_thr = 5, 4, 3, 2. Below the thesis rung n_robust = 2: the losing bin of a pair is emptied, the
largest margin eq. 7.2.16 allows (measured: more robust to noise and to skinning at about twice the
thesis' tiny distortion, docs/coding.md).
"""
from __future__ import annotations

import math

from .._core import MeshError
from . import coding
from .._typing import IntArray
from typing import Iterator
from typing import Any

MODES = ("auto", "thesis")

# ``params="thesis"`` is the published set: beyond the numbers, the published carrier (the Laplacian
# length over the global mean edge length, eq. 7.1.5; docs/carrier.md) and radial's n_thr from Table 6.1
# (interpolated between the thesis' models, radial.default_n_thr), unless given explicitly.
THESIS_CHOICES = {"laplacian": {"carrier": "thesis"}, "radial": {"n_thr_rule": "table6.1"}}

# method -> rungs; a rung is a function (n_referenced) -> dict of parameters
LADDERS = {
    "laplacian": [(70, 46, 5), (50, 33, 2), (35, 23, 2), (25, 16, 2), (18, 12, 2), (12, 8, 2),
                  (8, 5, 2), (6, 4, 2), (4, 3, 2), (3, 2, 2)],
    "cho-mean": [64, 128],
    "cho-variance": [64, 128],
    "radial": [400],
}


def _rung_params(name: str, rung, n_ref: int) -> dict:
    if name == "laplacian":
        n_c, n_thr, n_robust = rung
        return {"K": int(math.ceil(n_ref / n_c)), "n_thr": n_thr, "n_robust": n_robust}
    return {"K": int(rung)}


def _n_referenced(mesh) -> int:
    return int(mesh.referenced().sum())


def _evaluate(mesh, m, given: dict, move_K=None):
    """Yield (rung index, params, ids, side) for the method's ladder, resolving lazily; rungs the
    mesh cannot take (e.g. fewer vertices than bins) are skipped; MeshError if none can.
    ``move_K(K)``: the bin count each rung uses instead of its own (key-dependent bins, keys.key_bins)."""
    n_ref = _n_referenced(mesh)
    first_error = None
    any_ok = False
    for i, rung in enumerate(LADDERS.get(m.name, [None])):
        q = {} if rung is None else _rung_params(m.name, rung, n_ref)
        if move_K is not None and "K" in q:
            q["K"] = move_K(q["K"])
        q.update({k: v for k, v in given.items() if v is not None})
        try:
            p = m.resolve(mesh, q)
        except MeshError as exc:
            first_error = first_error or exc
            continue
        ids, side = m.carriers(mesh, p)
        any_ok = True
        yield i, p, ids, side
    if not any_ok and first_error is not None:
        m.resolve(mesh, given)  # the published defaults' own error (e.g. "the mesh is too small ...")
        raise first_error


def choose(mesh: Mesh, m: Any, params: Any, method_params: dict, n_data: int | None,
           need: int | None = None, move_K: Any = None) -> tuple[dict[str, Any], IntArray, Any, dict[str, Any]]:
    """(params, carrier ids, side info, choice record) for method ``m`` on ``mesh``.

    ``params``: "auto", "thesis", or a dict of explicit parameters (merged with ``method_params``);
    ``n_data``: payload bits (None: no payload yet, auto returns the first rung); ``need``: the
    carriers wanted, instead of those the payload needs (copy tracing); ``move_K``: see
    :func:`_evaluate` (auto only: every rung's K is moved, then the first that fits is chosen)."""
    given = dict(method_params)
    if isinstance(params, dict):
        given.update(params)
        params = "given" if params else "auto"
    if params not in MODES and params != "given":
        raise MeshError(f"params must be 'auto', 'thesis' or a dict of parameters, got {params!r}")
    if params == "thesis":
        given = {**THESIS_CHOICES.get(m.name, {}), **{k: v for k, v in given.items() if v is not None}}
    if params in ("thesis", "given"):
        p = m.resolve(mesh, given)
        ids, side = m.carriers(mesh, p)
        return p, ids, side, {"mode": params}
    if need is None:
        need = None if n_data is None else coding.min_carriers(n_data)
    best, largest, rule = None, None, 1
    for cand in _evaluate(mesh, m, given, move_K):
        if need is None or len(cand[2]) >= need:
            best = cand
            break
        if largest is None or len(cand[2]) > len(largest[2]):
            largest = cand
    if best is None:
        best, rule = largest, 2
    i, p, ids, side = best
    return p, ids, side, {"mode": "auto", "ladder": "v1", "rung": int(i), "rule": rule,
                          "needed_carriers": need, "capacity": int(len(ids)),
                          **({"key_bins": True} if move_K is not None else {})}


# What the automatic choice falls back to, per method, when no rung of the default carrier takes the
# mark (only when the user did not choose the carrier): the published carrier (docs/carrier.md).
FALLBACK_PARAMS = {"laplacian": {"carrier": "thesis"}}


def fallbacks(mesh: Mesh, m: Any, method_params: dict, choice: dict,
              move_K: Any = None) -> Iterator[tuple[dict[str, Any], IntArray, Any, dict[str, Any]]]:
    """What to try, in turn, when the chosen rung's mark does not take on the mesh (rare; e.g. many
    small parts of 36-gons): the later rungs that also fit the payload, then (if the user did not
    choose it) the method's fallback carrier (:data:`FALLBACK_PARAMS`) with its own ladder. Each item is
    as ``choose`` returns it; deterministic. Not used for ``params="thesis"`` or explicit parameters.

    ``mesh``: a Mesh with ``V`` (n, 3) float64; each item carries its carrier ids (c,) int."""
    if choice.get("mode") != "auto" or choice.get("rule") != 1:
        return
    need = choice.get("needed_carriers")
    start = int(choice["rung"])
    alt = FALLBACK_PARAMS.get(m.name, {})
    plans = [(dict(method_params), start + 1)]
    if alt and all(method_params.get(k) is None for k in alt):
        plans.append(({**method_params, **alt}, 0))
    for given, first in plans:
        for i, p, ids, side in _evaluate(mesh, m, given, move_K):
            if i >= first and (need is None or len(ids) >= need):
                yield p, ids, side, {**choice, "rung": int(i), "capacity": int(len(ids)),
                                     "fallback_from": start, **({"fallback": alt} if given.keys() - method_params.keys() else {})}


def longest_payload_bits(mesh: Mesh, m: Any, method_params: dict, move_K: Any = None) -> int:
    """The longest payload (bits) ``params="auto"`` can embed: the largest over the ladder."""
    return max((coding.max_data_bits(len(ids)) for _, _, ids, _ in _evaluate(mesh, m, dict(method_params), move_K)),
               default=0)
