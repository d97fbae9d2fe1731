"""Yang's radial-histogram watermark with a PCA origin (thesis §6.1-6.2).

The distances ``rho_i = ||v_i - o||`` (eq. 6.1.1) are taken about an origin ``o`` on the first principal
axis: the mean of the right-most half of the vertices projected on the axis (§6.1.1; the axis sign is
meshmark's PCA rule, positive skewness, ``docs/mesh_model.md``). ``K`` bins of width
``(rho_max - rho_min) / K`` (eqs. 6.1.2-6.1.3); pairs (B2, B3), (B4, B5), ... with B1, B_K (and B_{K-1}
for odd K) never used; a pair with at least one element is embeddable (eq. 6.1.4). A bit is written
by moving ``n_mov`` radii (cases 1-3, eq. 6.1.7) into the other bin of the pair (eq. 6.1.5) so that
the count difference reaches ``n_thr`` (eq. 6.1.6), and read as which bin is larger (eq. 6.2.10:
bit 1 <=> ``|B_k| > |B_k+1|``).

Defaults: ``K = 400`` (§6.3.2); ``n_thr = max(1, round(0.0245 N^0.726 400 / K))`` (:func:`default_n_thr`,
a power law fitted to Table 6.1; docs/radial.md §2). ``params="thesis"`` and :func:`embed_bits` take
n_thr from Table 6.1 itself, interpolated between its models (continuous in N; the published values at
the thesis' vertex counts).

:func:`embed` / :func:`extract` go through the framework (keys, framing, keyfile, detection; the frame is
repeated over every embeddable pair); :func:`embed_bits` / :func:`extract_bits` are the thesis' use (bit
``i`` in the ``i``-th embeddable pair, no key).
"""
from __future__ import annotations

import numpy as np

from .. import _core
from .._core import MeshError
from ..ranges import check_int
from ..mesh import FacesLike, Mesh, MeshLike, vertices_and_mask
from . import framework
from .keyfile import Keyfile
from .._typing import ArrayLike, FloatArray, IntArray, PathLike, Progress, UInt8Array
from typing import Any

NAME = "radial"
DEFAULTS = {"K": 400, "n_thr": None, "origin_mode": "axis", "origin_iters": 0}

#: Table 6.1 of the thesis (K = 400): model -> (#vertices, n_thr).
TABLE_6_1 = {"bunny": (34835, 43), "rabbit": (70658, 80), "venus": (100759, 100), "dragon": (50000, 75),
             "cow": (2904, 8)}


# Table 6.1's points in ascending vertex count, and the power law fitted to them (docs/radial.md §2).
_T61_N = np.array(sorted(n for n, _ in TABLE_6_1.values()), dtype=np.float64)
_T61_THR = np.array([thr for _, thr in sorted(TABLE_6_1.values())], dtype=np.float64)
N_THR_RULES = ("power", "table6.1")


def _power_law(n: float) -> float:
    return 0.0245 * n ** 0.726


def default_n_thr(n_vertices: int, K: int = 400, rule: str = "power") -> int:
    """The default eq. 6.1.6 count difference for ``n_vertices`` referenced vertices and ``K`` bins,
    continuous in the vertex count (it moves by at most 1 from one count to the next).

    ``rule="power"`` (the default parameters): ``max(1, round(0.0245 N^0.726 400 / K))``, the power law
    fitted to Table 6.1. ``rule="table6.1"`` (``params="thesis"`` and the thesis' own use,
    :func:`embed_bits`): log-log linear interpolation through Table 6.1's five (N, n_thr) points, so the
    thesis' models get the published values (Bunny 43, Rabbit 80, Venus 100, Dragon 75, Cow 8), and
    the power law scaled to meet the end points beyond them."""
    if rule not in N_THR_RULES:
        raise MeshError(f"n_thr rule must be one of {', '.join(N_THR_RULES)}, got {rule!r}")
    n = max(1.0, float(n_vertices))
    if rule == "power":
        thr = _power_law(n)
    elif n <= _T61_N[0]:
        thr = _power_law(n) * _T61_THR[0] / _power_law(_T61_N[0])
    elif n >= _T61_N[-1]:
        thr = _power_law(n) * _T61_THR[-1] / _power_law(_T61_N[-1])
    else:
        thr = float(np.exp(np.interp(np.log(n), np.log(_T61_N), np.log(_T61_THR))))
    return max(1, int(round(thr * 400.0 / K)))


def pair_counts(counts: np.ndarray, K: int) -> tuple[IntArray, IntArray, IntArray]:
    """(first bin a (p,), |B_a| (p,), |B_a+1| (p,)) of the pairs (B2,B3), ... (0-based a = 1, 3, ...)."""
    a = np.arange((K - 2) // 2) * 2 + 1
    return a, counts[a], counts[a + 1]


class _Radial:
    name = NAME

    def resolve(self, mesh: Mesh, params: dict) -> dict:
        params = dict(params)
        rule = params.pop("n_thr_rule", "power")  # "table6.1" from params="thesis" (auto.THESIS_CHOICES)
        p = framework.merge_params("radial", DEFAULTS, params)
        p["K"], p["origin_iters"] = check_int("K", p["K"]), check_int("origin_iters", p["origin_iters"])
        if p["origin_mode"] not in ("axis", "vertices"):
            raise MeshError(f"origin_mode must be 'axis' or 'vertices', got {p['origin_mode']!r}")
        n = int(mesh.referenced().sum())
        if n < p["K"]:
            raise MeshError(f"the mesh has {n} referenced vertices but K = {p['K']} bins were asked for: "
                            "fewer vertices than bins")
        p["n_thr"] = default_n_thr(n, p["K"], rule) if p["n_thr"] is None else check_int("n_thr", p["n_thr"])
        return p

    def describe(self, p: dict) -> str:
        return f"K={p['K']}, n_thr={p['n_thr']}"

    def counts(self, mesh: Mesh, p: dict):
        return _core.radial_counts(mesh.V, mesh.referenced(), p["K"], p["origin_mode"])[0]

    def carriers(self, mesh: Mesh, p: dict):
        _, ca, cb = pair_counts(self.counts(mesh, p), p["K"])
        return np.flatnonzero(ca + cb >= 1), {}  # eq. 6.1.4

    def embed(self, mesh: Mesh, p: dict, side: dict, ids, bits):
        pm = np.where(np.asarray(bits) > 0, 1, -1)
        r = _core.radial_embed(mesh.V, mesh.referenced(), p["K"], [int(i) for i in ids], pm.tolist(), p["n_thr"],
                               p["origin_mode"], p["origin_iters"])
        st = {"n_moved": int(r["n_moved"])}
        if r["origin_drift"] >= 0:
            st["origin_drift"] = float(r["origin_drift"])
        return r["V"], side, st

    def extract(self, mesh: Mesh, p: dict, side: dict, ids):
        _, ca, cb = pair_counts(self.counts(mesh, p), p["K"])
        ids = np.asarray(ids, np.int64)
        if ids.size and ids.max() >= (p["K"] - 2) // 2:
            raise MeshError("keyfile lists a carrier beyond the histogram's pairs (corrupt keyfile?)")
        c1, c2 = ca[ids], cb[ids]
        # eq. 6.2.10; signed reliability = count margin relative to the pair size (> 0: bit 1)
        return (c1 > c2).astype(np.uint8), (c1 - c2) / np.maximum(c1 + c2, 1)


METHOD = _Radial()
framework.register(METHOD)


def capacity(V: MeshLike, F: FacesLike = None, **params: Any) -> int:
    """Number of embeddable pairs (eq. 6.1.4) = carrier bits, before framing (16 bits) is subtracted.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.capacity(V, F, method=NAME, **params)


def embed(V: MeshLike, F: FacesLike = None, payload: str | bytes | None = None, key: str | int | None = None,
          progress: Progress = None, **params: Any) -> framework.EmbedResult:
    """Embed ``payload`` under ``key``. Parameters: ``K`` (400), ``n_thr`` (Table 6.1 / rule),
    ``origin_mode`` ("axis" or "vertices"), ``origin_iters`` (0).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.embed(V, F, payload=payload, key=key, method=NAME, progress=progress, **params)


def extract(V: MeshLike, F: FacesLike = None, keyfile: Keyfile | PathLike | None = None,
            key: str | int | None = None, progress: Progress = None) -> framework.ExtractResult:
    """Blind extraction and detection with a keyfile written by :func:`embed`.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.extract(V, F, keyfile=keyfile, key=key, progress=progress)


def origin(V: MeshLike, F: FacesLike = None, origin_mode: str = "axis") -> tuple[FloatArray, FloatArray, float]:
    """§6.1.1: ``(o (3,), principal axis u (3,), standardised skewness along u)``."""
    V, mask = vertices_and_mask(V, F)
    return _core.radial_origin(V, mask, origin_mode)


# --- the thesis' own interface: bit i in the i-th embeddable pair, no key ----------------------
def embed_bits(V: MeshLike, F: FacesLike = None, bits: ArrayLike = None, K: int = 400, n_thr: int | None = None,
               origin_mode: str = "axis",
               origin_iters: int = 0) -> tuple[FloatArray, dict[str, Any]]:
    """§6.1 as written: bit ``i`` (0/1) into the ``i``-th embeddable pair (B2,B3), (B4,B5), ...

    Returns ``(V' (n, 3) float64, info)`` with ``origin``, ``pairs`` (pair indices used), ``n_mov``,
    ``n_moved``, ``n_thr``, ``origin_drift``. MeshError if the mesh has fewer embeddable pairs than bits.
    """
    V, mask = vertices_and_mask(V, F)
    b = np.asarray(bits).ravel()
    if b.size == 0 or not np.isin(b, (0, 1)).all():
        raise MeshError("bits must be a non-empty sequence of 0 and 1")
    n = int(mask.sum())
    K = check_int("K", K)
    n_thr = default_n_thr(n, K, "table6.1") if n_thr is None else check_int("n_thr", n_thr)
    r = _core.radial_embed(V, mask, K, None, (2 * b.astype(int) - 1).tolist(), n_thr, origin_mode,
                           check_int("origin_iters", origin_iters))
    V2 = r.pop("V")
    r.update(pairs=np.asarray(r["pairs"]), n_thr=n_thr)
    return V2, r


def extract_bits(V: MeshLike, F: FacesLike = None, n_bits: int = 64, K: int = 400,
                 origin_mode: str = "axis") -> tuple[UInt8Array, dict[str, Any]]:
    """§6.2: origin and histogram from the mesh itself, embeddable pairs (eq. 6.2.8) in order,
    eq. 6.2.10. Returns ``(bits (n_bits,) uint8, counts (K,))`` (missing pairs read as 0)."""
    V, mask = vertices_and_mask(V, F)
    K = check_int("K", K)
    counts = _core.radial_counts(V, mask, K, origin_mode)[0]
    _, ca, cb = pair_counts(counts, K)
    emb = np.flatnonzero(ca + cb >= 1)[:n_bits]
    bits = np.zeros(n_bits, np.uint8)
    bits[: emb.size] = ca[emb] > cb[emb]
    return bits, counts
