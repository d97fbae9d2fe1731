"""Cho, Prost & Jung's vertex-norm watermarks (IEEE TSP 55(1), 2007; thesis §2.2.2, used in ch. 6-8).

The norms ``rho_i = ||v_i - c||`` of the referenced vertices about their centre of gravity ``c`` are
split into ``K`` bins of equal range and normalised to [0, 1] inside their bin; each bin carries one
bit through a histogram mapping with exponent ``k``, searched in steps of ``delta_k``:

* ``cho-mean`` (method I): ``x' = x^k`` until the bin mean is ``>= 1/2 + alpha`` (bit 1) or
  ``<= 1/2 - alpha`` (bit 0); extraction compares the mean with 1/2;
* ``cho-variance`` (method II): ``y = 2x - 1``, ``y' = sgn(y)|y|^k`` until ``mean y'^2`` is
  ``>= 1/3 + alpha`` or ``<= 1/3 - alpha``; extraction compares with 1/3.

Defaults: ``K = 64`` bins (thesis §8.2), ``delta_k = 0.001``, ``alpha = 0.04`` (mean, §7.4.4; §8.2 draws
it in [0.02, 0.06]) or ``0.16`` (variance, the midpoint of §8.2's [0.12, 0.20]). Every detail and
choice is in ``docs/radial.md`` §1.

As published, the method loses bits with no attack on small meshes: the marked mesh's centre of
gravity is not the one used to embed, and the mapping crowds values against the bin ends. The
default therefore adds two fixes, ``guard = 0.005`` (mapped values kept off the bin ends) and
``center_iters = 20`` (re-embedding about the marked mesh's centre until the two agree);
``thesis_exact=True`` runs the paper (both off).

Two interfaces:

* the framework methods (:func:`embed`, :func:`extract`, ``meshmark embed --method cho-mean``): keys,
  payload framing, repetition over the non-empty bins, keyfiles and detection as for every method;
* :func:`embed_bits` / :func:`extract_bits`: the paper's own use, bit ``n`` in bin ``n`` with no key
  (the experiments of ch. 6 and the steganalysis of §6.4 use it).
"""
from __future__ import annotations

import numpy as np

from .. import _core
from .._core import MeshError
from ..ranges import check_bool, check_float, check_int
from ..mesh import FacesLike, Mesh, MeshLike, vertices_and_mask
from . import framework
from .keyfile import Keyfile
from .._typing import ArrayLike, FloatArray, PathLike, Progress, UInt8Array
from typing import Any

NAMES = {"mean": "cho-mean", "variance": "cho-variance"}
REFERENCE = {"mean": 0.5, "variance": 1.0 / 3.0}
ALPHA = {"mean": 0.04, "variance": 0.16}
ROBUST = {"guard": 0.005, "center_iters": 20}
K_MAX_EXPONENT = 100.0


class _Cho:
    def __init__(self, kind: str):
        self.kind = kind
        self.name = NAMES[kind]
        self.defaults = {"K": 64, "alpha": ALPHA[kind], "delta_k": 0.001, "guard": None, "center_iters": None,
                         "thesis_exact": False}

    # -- parameters -----------------------------------------------------------------------------
    def resolve(self, mesh: Mesh, params: dict) -> dict:
        p = framework.merge_params(self.name, self.defaults, params)
        p["thesis_exact"] = check_bool("thesis_exact", p["thesis_exact"])
        for k in ("guard", "center_iters"):
            if p[k] is None:
                p[k] = 0 if p["thesis_exact"] else ROBUST[k]
            elif p["thesis_exact"] and p[k]:
                raise MeshError(f"thesis_exact runs the paper without {k}; do not set both")
        p["K"], p["center_iters"] = check_int("K", p["K"]), check_int("center_iters", p["center_iters"])
        lim = 0.5 if self.kind == "mean" else 1.0 / 3.0
        p["alpha"] = check_float("alpha", p["alpha"], 0.0, lim, low_open=True, high_open=True)
        p["delta_k"] = check_float("delta_k", p["delta_k"], 0.0, 1.0, low_open=True, high_open=True)
        p["guard"] = check_float("guard", p["guard"], 0.0, 0.25, high_open=True)
        n = int(mesh.referenced().sum())
        if n < p["K"]:
            raise MeshError(f"the mesh has {n} referenced vertices but K = {p['K']} bins were asked for: "
                            "fewer vertices than bins")
        return p

    def describe(self, p: dict) -> str:
        return f"K={p['K']}, alpha={p['alpha']:g}"

    # -- carriers: the non-empty bins -----------------------------------------------------------
    def statistics(self, mesh: Mesh, p: dict):
        return _core.cho_statistics(mesh.V, mesh.referenced(), p["K"], self.kind)

    def carriers(self, mesh: Mesh, p: dict):
        _, counts, _ = self.statistics(mesh, p)
        return np.flatnonzero(counts >= 1), {}

    # -- embed / extract ------------------------------------------------------------------------
    def embed(self, mesh: Mesh, p: dict, side: dict, ids, bits):
        pm = np.where(np.asarray(bits) > 0, 1, -1)
        r = _core.cho_embed(mesh.V, mesh.referenced(), p["K"], [int(i) for i in ids], pm.tolist(), self.kind,
                            p["alpha"], p["delta_k"], K_MAX_EXPONENT, p["guard"], p["center_iters"])
        return r["V"], side, {"n_moved": int(r["n_moved"]), "n_failed_bins": len(r["failed_bins"]),
                              "center_drift": float(r["center_drift"])}

    def extract(self, mesh: Mesh, p: dict, side: dict, ids):
        stat, _, _ = self.statistics(mesh, p)
        ids = np.asarray(ids, np.int64)
        if ids.size and ids.max() >= p["K"]:
            raise MeshError("keyfile lists a carrier beyond the histogram's bins (corrupt keyfile?)")
        s = stat[ids] - REFERENCE[self.kind]
        return (s > 0).astype(np.uint8), s / p["alpha"]  # signed reliability (> 0: bit 1)


MEAN = _Cho("mean")
VARIANCE = _Cho("variance")
framework.register(MEAN)
framework.register(VARIANCE)
METHODS = {"mean": MEAN, "variance": VARIANCE}


def _name(method: str) -> str:
    if method not in NAMES:
        raise MeshError(f"Cho method must be 'mean' or 'variance', got {method!r}")
    return NAMES[method]


def capacity(V: MeshLike, F: FacesLike = None, method: str = "mean", **params: Any) -> int:
    """Number of non-empty bins = carrier bits, before framing (16 bits) is subtracted.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.capacity(V, F, method=_name(method), **params)


def embed(V: MeshLike, F: FacesLike = None, payload: str | bytes | None = None, key: str | int | None = None,
          method: str = "mean", progress: Progress = None, **params: Any) -> framework.EmbedResult:
    """Embed ``payload`` under ``key`` with Cho's mean (``method="mean"``) or variance method.

    Parameters: ``K`` bins (64), ``alpha`` (0.04 mean / 0.16 variance), ``delta_k`` (0.001), ``guard``
    (0.005), ``center_iters`` (20), ``thesis_exact`` (False: guard and center_iters default to 0 when True).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    return framework.embed(V, F, payload=payload, key=key, method=_name(method), progress=progress, **params)


def extract(V: MeshLike, F: FacesLike = None, keyfile: Keyfile | PathLike | None = None,
            key: str | int | None = None, progress: Progress = None) -> framework.ExtractResult:
    """Blind extraction and detection with a keyfile written by :func:`embed`.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.extract(V, F, keyfile=keyfile, key=key, progress=progress)


# --- the paper's own interface: bit n in bin n, no key ------------------------------------------
def embed_bits(V: MeshLike, F: FacesLike = None, bits: ArrayLike = None, method: str = "mean", K: int | None = None,
               alpha: float | None = None,
               delta_k: float = 0.001, guard: float = 0.0, center_iters: int = 0,
               k_max: float = K_MAX_EXPONENT) -> tuple[FloatArray, dict[str, Any]]:
    """Cho's embedding as published (``guard = center_iters = 0``): bit ``n`` (0/1) into bin ``n``.

    ``V`` (n, 3) with faces ``F`` (only referenced vertices take part) or a point set (``F=None``);
    ``K`` defaults to ``len(bits)``. Returns ``(V' (n, 3) float64, info)`` with ``info`` holding the
    exponents ``k`` (K,), ``failed_bins``, ``center``, ``center_drift``, ``center_iters`` and ``n_moved``.
    """
    _name(method)
    V, mask = vertices_and_mask(V, F)
    b = np.asarray(bits).ravel()
    if b.size == 0 or not np.isin(b, (0, 1)).all():
        raise MeshError("bits must be a non-empty sequence of 0 and 1")
    K = check_int("K", b.size if K is None else K)
    if b.size > K:
        raise MeshError(f"{b.size} bits do not fit {K} bins (one bit per bin)")
    alpha = ALPHA[method] if alpha is None else float(alpha)
    r = _core.cho_embed(V, mask, K, list(range(b.size)), (2 * b.astype(int) - 1).tolist(), method, alpha,
                        float(delta_k), float(k_max), float(guard), check_int("center_iters", center_iters))
    V2 = r.pop("V")
    return V2, r


def extract_bits(V: MeshLike, F: FacesLike = None, n_bits: int = 64, method: str = "mean",
                 K: int | None = None) -> tuple[UInt8Array, dict[str, Any]]:
    """Blind detection as published: ``(bits (n_bits,) uint8, statistics (K,))``, bit = [stat > 1/2 or 1/3]."""
    _name(method)
    V, mask = vertices_and_mask(V, F)
    K = check_int("K", n_bits if K is None else K)
    stat, _, _ = _core.cho_statistics(V, mask, K, method)
    return (stat[:n_bits] > REFERENCE[method]).astype(np.uint8), stat
