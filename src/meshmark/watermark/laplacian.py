"""The Laplacian-coordinate watermark (thesis ch. 7), fit for real files.

The mark lives in the histogram of the Laplacian lengths ``d_i = ||L_i||``, ``L = K X`` with ``K`` the
Kirchhoff matrix of the edge graph (eqs. 7.1.2-7.1.5): K bins, adjacent pairs (B2, B3), (B4, B5), ...
(eq. 7.2.12), one bit per valid pair (``f >= n_thr``, eq. 7.1.8) written as which bin is larger
(eq. 7.1.9) by moving the lengths nearest the shared edge (eqs. 7.2.13-7.2.16), projecting the
Laplacian vectors to their new lengths (eq. 7.2.19) and solving one sparse system. Extraction is blind
(eqs. 7.3.20-7.3.21): it needs only the marked mesh and the keyfile, never the original.

Defaults are those of §7.4: ``K = ceil(N / 70)`` (N referenced vertices), ``n_thr = 46``,
``n_robust = 5``, ``eps = 1e-5``. ``thesis_exact=True`` runs §7.2 to the letter; the default adds the
fixes of ``docs/laplacian.md`` (scale normalisation, a margin in every pair, lengths kept off bin
edges, a drift-free solve, carriers listed in the keyfile against desynchronisation).

Quads and n-gons are used as they are: the Laplacian is that of the polygon edge graph.
"""
from __future__ import annotations

import math

import numpy as np

from .. import _core
from .._core import MeshError
from .. import ranges as _ranges
from ..ranges import check_bool, check_float, check_int
from ..mesh import as_mesh, FacesLike, Mesh, MeshLike
from . import framework
from .keyfile import Keyfile
from .._typing import PathLike, Progress
from typing import Any

NAME = "laplacian"
SOLVERS = {"iterative": 5, "direct": 0}  # PCG steps per round (docs/laplacian.md); 0 = one exact solve
MAX_SOLVE_ROUNDS = 8  # rounds of the iterative reconstruction
# The binned scalar (native/include/meshmark/laplacian_carrier.h, docs/carrier.md): name -> (native
# kind, asinh compression, divided by the global mean edge length). "thesis" is ||L_i|| (eq. 7.1.5)
# over the global mean edge length; "local" ||L_i|| / l_i and "normal" (L_i . n_i) / l_i use the mean
# length l_i of the vertex's own edges; "cot_*" use the cotangent Laplacian; "normal_global" is
# (L_i . n_i) over the global mean edge length. (The native asinh compression is measured by
# examples/carrier_skinning.py only: it loses bits to OBJ rounding.) Keyfiles without the field use "thesis".
CARRIERS = {"thesis": (0, 0.0, True), "local": (1, 0.0, False), "normal": (2, 0.0, False),
            "cot_local": (3, 0.0, False), "cot_normal": (4, 0.0, False), "normal_global": (5, 0.0, True)}
assert tuple(CARRIERS) == _ranges.LAPLACIAN_CARRIERS  # the names the keyfile schema accepts
DEFAULT_CARRIER = "local"  # docs/carrier.md: detected on more frames of the Blender rigs
DEFAULTS = {"K": None, "n_thr": 46, "n_robust": 5, "eps": 1e-5, "thesis_exact": False, "solver": "iterative",
            "carrier": DEFAULT_CARRIER}


def carrier_of(p: dict) -> str:
    """The carrier recorded in resolved parameters (keyfiles written before the option: the thesis')."""
    return p.get("carrier") or "thesis"


def _carrier_field(mesh: Mesh, carrier: str):
    """(E, s, scale): edges, the carrier scalar of every vertex (native) and the global unit it was
    divided by (the mean edge length, or 1 for the locally normalised carriers)."""
    if carrier not in CARRIERS:
        raise MeshError(f"carrier must be one of {', '.join(CARRIERS)}, got {carrier!r}")
    E = _edges(mesh)
    kind, compress, global_unit = CARRIERS[carrier]
    if carrier == "thesis":  # the extraction's one-pass path (edges only)
        d, mel = _core.laplacian_lengths_scaled(mesh.V, E, 0.0)
        return E, d / mel, mel
    scale = _core.mean_edge_length(mesh.V, E) if global_unit else 1.0
    return E, _core.laplacian_carrier(mesh.V, E, _triangles(mesh, carrier), kind, scale, compress), scale


def carrier_values(mesh: Mesh, carrier: str) -> np.ndarray:
    """(n,) carrier scalar of every vertex (native, laplacian_carrier.h); "thesis" in mean edge lengths."""
    return _carrier_field(mesh, carrier)[1]


def _edges(mesh: Mesh) -> np.ndarray:
    return mesh.edges()


NO_TRIANGLES = np.zeros((0, 3), np.int32)


def _triangles(mesh: Mesh, carrier: str = "normal") -> np.ndarray:
    """(t, 3) int32 triangles for the carriers that need normals or cotangent weights (cached with the
    topology); an empty array for "thesis" and "local", which use the edges only."""
    if carrier in ("thesis", "local"):
        return NO_TRIANGLES
    topo = mesh._topology
    if "triangles" not in topo:
        topo["triangles"] = np.ascontiguousarray(mesh.triangles, dtype=np.int32)
    return topo["triangles"]


def mean_edge_length(V: np.ndarray, E: np.ndarray) -> float:
    """Mean edge length (model units): the scale unit of the normalised Laplacian lengths.

    ``V`` (n, 3) float64 positions, ``E`` (e, 2) integer edges."""
    return float(_core.mean_edge_length(V, E))


def laplacian_lengths(V: MeshLike, F: FacesLike = None, eps: float = 0.0) -> np.ndarray:
    """(n,) lengths of the Laplacian coordinates, eqs. 7.1.2-7.1.5 (model units; 0 for unreferenced)."""
    mesh = as_mesh(V, F)
    return _core.laplacian_lengths(mesh.V, _edges(mesh), eps)


class _Laplacian:
    name = NAME

    # -- parameters -----------------------------------------------------------------------------
    def resolve(self, mesh: Mesh, params: dict) -> dict:
        p = framework.merge_params("laplacian", DEFAULTS, params)
        n_ref = int(mesh.referenced().sum())
        auto_K = p["K"] is None
        if auto_K:
            p["K"] = int(math.ceil(n_ref / 70))  # §7.4: K = ceil(N / N_c), N_c = 70
        p["K"] = check_int("K", p["K"], note=" (the mesh is too small for K = ceil(N/70))" if auto_K else "")
        p["n_thr"], p["n_robust"] = check_int("n_thr", p["n_thr"]), check_int("n_robust", p["n_robust"])
        p["eps"] = check_float("eps", p["eps"], 0.0, 1.0, low_open=True)
        p["thesis_exact"] = check_bool("thesis_exact", p["thesis_exact"])
        if p["solver"] not in SOLVERS:
            raise MeshError(f"solver must be one of {', '.join(SOLVERS)}, got {p['solver']!r}")
        if p["carrier"] not in CARRIERS:
            raise MeshError(f"carrier must be one of {', '.join(CARRIERS)}, got {p['carrier']!r}")
        if p["thesis_exact"]:  # the thesis' own scalar; the default carrier is replaced, another one refused
            if p["carrier"] not in ("thesis", DEFAULT_CARRIER):
                raise MeshError(f"thesis_exact=True uses the thesis carrier; got carrier={p['carrier']!r}")
            p["carrier"] = "thesis"
        return p

    def describe(self, p: dict) -> str:
        return f"K={p['K']}, n_thr={p['n_thr']}"

    # -- the histogram --------------------------------------------------------------------------
    def _lengths(self, mesh: Mesh, p: dict):
        """(E, d / scale, scale): edges, normalised Laplacian lengths (eq. 7.1.5) and the scale unit,
        computed once per mesh (native, one pass over the edges)."""
        return self._state(mesh, p)["lengths"]

    def _state(self, mesh: Mesh, p: dict) -> dict:
        """What is derived from these positions, kept in one cache entry on the mesh (the cache holds the
        two most recent entries): the lengths, the sorted referenced lengths and the range factors
        found, so that the embedding's check on the marked mesh and its re-reading share them."""
        eps = p["eps"] if p["thesis_exact"] else 0.0
        carrier = carrier_of(p)

        def compute():
            E = _edges(mesh)
            if carrier != "thesis" and not p["thesis_exact"]:  # laplacian_carrier.h
                return {"lengths": _carrier_field(mesh, carrier)}
            d, mel = _core.laplacian_lengths_scaled(mesh.V, E, eps)
            scale = 1.0 if p["thesis_exact"] else mel
            return {"lengths": (E, d / scale, scale)}

        return mesh.cached(("laplacian_lengths", eps, bool(p["thesis_exact"]), carrier), compute)

    def _sorted(self, mesh: Mesh, p: dict) -> np.ndarray:
        """The referenced vertices' carrier values, sorted (cached with the lengths)."""
        st = self._state(mesh, p)
        if "sorted" not in st:
            st["sorted"] = np.sort(st["lengths"][1][mesh.referenced() == 1])
        return st["sorted"]

    def _range(self, mesh: Mesh, p: dict, lo: float, hi: float, ids: np.ndarray) -> float:
        """The range search's factor for these carriers (cached with the lengths)."""
        st = self._state(mesh, p).setdefault("range", {})
        ids = np.asarray(ids, np.int64)
        key = (float(lo), float(hi), int(p["K"]), ids.tobytes())
        if key not in st:
            st[key] = _range_factor(self._sorted(mesh, p), lo, hi, p["K"], ids)
        return st[key]

    def carriers(self, mesh: Mesh, p: dict):
        E, d, scale = self._lengths(mesh, p)
        mask = mesh.referenced()
        lo, hi = float(d[mask == 1].min()), float(d[mask == 1].max())
        _, counts = _core.laplacian_histogram(d, p["K"], lo, hi, mask)
        f = counts[1:-1:2][: (p["K"] - 2) // 2] + counts[2::2][: (p["K"] - 2) // 2]
        ids = np.flatnonzero(f >= p["n_thr"])  # eq. 7.1.8
        unit = "none" if p["thesis_exact"] else "mean_edge_length" if CARRIERS[carrier_of(p)][2] else "local"
        return ids, {"lo": lo, "hi": hi, "scale": unit}

    def _histogram(self, mesh: Mesh, p: dict, side: dict):
        E, d, scale = self._lengths(mesh, p)
        bins, counts = _core.laplacian_histogram(d, p["K"], side["lo"], side["hi"], mesh.referenced())
        return E, bins, counts, scale

    # -- embed / extract ------------------------------------------------------------------------
    def embed(self, mesh: Mesh, p: dict, side: dict, ids, bits):
        E, bins, counts, scale = self._histogram(mesh, p, side)
        pm = np.where(np.asarray(bits) > 0, 1, -1)
        if not p["thesis_exact"]:
            bins, counts = _recruit(self._lengths(mesh, p)[1], bins, counts, side, p["K"], ids, pm)
        V, _, n_moved, rounds, iters = _core.laplacian_embed(
            mesh.V, E, bins, counts, side["lo"], side["hi"], [int(i) for i in ids], pm.tolist(), p["n_robust"],
            p["eps"], p["thesis_exact"], scale, SOLVERS[p.get("solver", "iterative")], MAX_SOLVE_ROUNDS,
            CARRIERS[carrier_of(p)][0],
            _triangles(mesh, carrier_of(p)), CARRIERS[carrier_of(p)][1])
        side = dict(side)
        if not p["thesis_exact"]:  # express the range in units of the marked mesh's mean edge length
            marked = mesh.with_vertices(V)
            _, _, scale_marked = self._lengths(marked, p)
            r = scale / scale_marked  # 1 for the locally normalised carriers
            side["lo"], side["hi"] = side["lo"] * r, side["hi"] * r
            # The range search may be used at extraction only if, on the marked mesh itself, it finds
            # t = 1: on skewed histograms (huge first bins) a shifted range can score higher by chance.
            t = self._range(marked, p, side["lo"], side["hi"], ids)
            side["range_search"] = bool(side.get("range_search", True) and abs(t - 1.0) < 1e-3)
        return V, side, {"n_moved": int(n_moved), "n_solve_rounds": int(rounds), "n_pcg_iterations": int(iters)}

    def extract(self, mesh: Mesh, p: dict, side: dict, ids):
        ids = np.asarray(ids, np.int64)
        if ids.size and ids.max() >= (p["K"] - 2) // 2:
            raise MeshError("keyfile lists a carrier beyond the histogram's pairs (corrupt keyfile?)")
        d = self._sorted(mesh, p)
        lo, hi, K = side["lo"], side["hi"], p["K"]
        t = 1.0
        if not p["thesis_exact"] and side.get("range_search", True):
            t = self._range(mesh, p, lo, hi, ids)
        c1, c2 = _pair_counts(d, lo * t, hi * t, K, ids)
        bits = (c1 >= c2).astype(np.uint8)  # eq. 7.1.10 / §7.3: +1 if |B_k| >= |B_k+1|
        # signed reliability: the pair's count margin relative to its size (> 0: bit 1)
        soft = (c1 - c2) / np.maximum(c1 + c2, 1)
        return bits, soft


def _recruit(d: np.ndarray, bins: np.ndarray, counts: np.ndarray, side: dict, K: int, ids, pm: np.ndarray):
    """(bins, counts) with one element lent to every carrier pair that is empty and must read -1.

    An empty pair reads +1 (|B_k1| >= |B_k2| at 0 = 0, eq. 7.1.10) and the selection (eqs.
    7.2.13-7.2.16) has nothing to move, so -1 could never be written: this happens to a copy of
    ``tracing.issue`` whose informed pattern and neighbouring carriers push a small pair's few
    lengths out of it. The referenced element nearest (in carrier value) to the centre of B_k2, outside
    the pairs being embedded, is counted in B_k1; the selection then moves it to B_k2 (its centre,
    eq. 7.2.15 with an empty winning bin)."""
    ids = np.asarray(ids, np.int64)
    j = ids[(pm < 0) & (counts[2 * ids + 1] + counts[2 * ids + 2] == 0)]
    if j.size == 0:
        return bins, counts
    bins, counts = np.array(bins), np.array(counts)
    busy = np.zeros(K, bool)
    busy[2 * ids + 1] = busy[2 * ids + 2] = True
    free = np.flatnonzero((bins >= 0) & ~busy[bins])
    delta = (side["hi"] - side["lo"]) / K
    for k in j:  # the few empty pairs only
        if free.size == 0:
            break
        centre = side["lo"] + delta * (2 * k + 2.5)
        i = int(np.argmin(np.abs(d[free] - centre)))
        v = free[i]
        counts[bins[v]] -= 1
        bins[v], counts[2 * k + 1] = 2 * k + 1, counts[2 * k + 1] + 1
        free = np.delete(free, i)
    return bins, counts


def _pair_counts(d_sorted: np.ndarray, lo: float, hi: float, K: int, ids: np.ndarray):
    """|B_k|, |B_k+1| of the carrier pairs ids (eq. 7.1.6) in the ascending lengths d_sorted; bins are
    half-open [edge_k, edge_k+1) as in laplacian_histogram; values outside [lo, hi] are not counted."""
    c1, c2 = _core.laplacian_pair_counts(d_sorted, lo, hi, K, np.asarray(ids, np.int64).tolist())
    return np.asarray(c1), np.asarray(c2)


def _range_factor(d_sorted, lo, hi, K, ids, span=0.1, min_gain=0.05) -> float:
    """The factor t in [1 - span, 1 + span] whose range (t lo, t hi) gives the carrier pairs the
    largest mean relative margin |c1 - c2| / (c1 + c2) (native, ``laplacian_range_factor.h``): a
    deformation or smoothing changes the mean edge length (our scale unit) by up to a few per cent,
    which shifts far bins by several bin widths (docs/laplacian.md, "Beyond the thesis" (c)). The
    score ignores the bit values, so it is the same for every key. Coarse grid (0.1 % steps), then a
    fine one (0.004 % steps) around the best (the coarse scan scores at most 256 evenly spaced
    carriers, the fine one all); t is used only if it raises the score by more than
    ``min_gain`` over t = 1."""
    return float(_core.laplacian_range_factor(d_sorted, lo, hi, K, np.asarray(ids, np.int64).tolist(), span, min_gain))


METHOD = _Laplacian()
framework.register(METHOD)


def capacity(V: MeshLike, F: FacesLike = None, **params: Any) -> int:
    """Carrier bits (valid bin pairs, eq. 7.1.8) before coding; ``params``/``n_data`` as in :func:`meshmark.watermark.framework.capacity`.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.capacity(V, F, method=NAME, **params)


def embed(V: MeshLike, F: FacesLike = None, payload: str | bytes | None = None, key: str | int | None = None,
          progress: Progress = None, **params: Any) -> framework.EmbedResult:
    """Embed ``payload`` under ``key``; returns ``EmbedResult(V, keyfile, capacity, stats)``.

    Parameters (thesis §7.4 defaults): ``K`` bins (``ceil(N/70)``), ``n_thr`` (46), ``n_robust`` (5),
    ``eps`` (1e-5), ``thesis_exact`` (False); and the framework's ``weld`` (True: coincident vertices
    are merged first, N counts the welded vertices).
    """
    return framework.embed(V, F, payload=payload, key=key, method=NAME, progress=progress, **params)


def extract(V: MeshLike, F: FacesLike = None, keyfile: Keyfile | PathLike | None = None,
            key: str | int | None = None, progress: Progress = None) -> framework.ExtractResult:
    """Blind extraction and detection with a keyfile written by :func:`embed`.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    return framework.extract(V, F, keyfile=keyfile, key=key, progress=progress)


def extract_blind(V: MeshLike, F: FacesLike = None, K: int | None = None, n_thr: int = 46, eps: float = 1e-5,
                  thesis_exact: bool = True) -> np.ndarray:
    """The thesis' extraction with no side information at all (§7.3): bins from the mesh's own
    d_min/d_max, carriers = pairs with f >= n_thr, in order. Returns the raw bits (0/1, 1 = +1).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    Returns (c,) uint8."""
    mesh = as_mesh(V, F)
    p = METHOD.resolve(mesh, {"K": K, "n_thr": n_thr, "eps": eps, "thesis_exact": thesis_exact})
    ids, side = METHOD.carriers(mesh, p)
    return METHOD.extract(mesh, p, side, ids)[0]
