"""Method kinds of studies: how a method variant marks a mesh and how the mark is read back.

A study task is (mesh, method variant, seed, attack variant). The engine knows two sorts of method:

* the **framework** methods (the keys of :data:`meshmark.watermark.framework.METHODS`: keyed, framed
  payload, ``framework.embed`` / ``framework.extract`` with the keyfile);
* **registered kinds** (this module): anything else that turns ``(mesh, params, seed)`` into marked
  vertices and reads bits back from an attacked mesh. Built in: the thesis' own, published uses of
  Cho's and Yang's methods, raw bits and no key (``cho-mean-bits``, ``cho-variance-bits``,
  ``radial-bits``: :func:`meshmark.watermark.cho.embed_bits` / :func:`meshmark.watermark.radial.embed_bits`,
  bit n in bin / pair n, as ``examples/radial_robustness.py`` and ``examples/steganalysis_table.py``
  use them).

The hook is :func:`register_method_kind` (this is how another module, e.g. the steganalysis study of
issue 15, adds a task kind: register an embedder here and its features with
:func:`meshmark.study.register_measurement`; the task grid, keys, Parquet, pool / Dask, resume and the
store stay the engine's)::

    from meshmark.study import register_method_kind, Marked, Read

    def embed(mesh, params, seed, spec):          # pure function of its arguments
        bits = np.random.default_rng(seed).integers(0, 2, params["n_bits"])
        V = my_embed(mesh.V, mesh.triangles, bits, **params)
        return Marked(V=V, bits=bits, capacity=len(bits), carried=True)

    def extract(mesh, marked, params):            # the attacked mesh, the Marked of embed
        return Read.compare(marked.bits, my_extract(mesh.V, mesh.triangles, len(marked.bits)))

    register_method_kind("my-lsb", defaults={"n_bits": 64}, embed=embed, extract=extract)

Workers are separate processes, so the registration must run in each of them: do it at import time
of a module and either list the module in the spec (``[study] plugins = ["my.module"]``, imported by
the driver before the spec is checked and by every worker) or append its name to
:data:`PLUGIN_MODULES` (imported everywhere for every study).

What the measurements see for a registered kind: ``ctx.embed`` is the :class:`Marked`,
``ctx.extract()`` the :class:`Read` (computed once). ``nc`` is the normalized correlation (2 CDR - 1)
and ``cdr`` the fraction of bits read correctly, as for framework methods; ``correlation`` is C of
eq. 6.3.11; ``detection`` is the binomial decision on the matching bits (P(false alarm) < 1e-6, as the
framework's); ``message`` says whether every bit came back; ``capacity`` is the kind's capacity and
the bits embedded; ``carried`` whether the mark was readable on the unattacked marked mesh.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .._core import MeshError
from .._typing import ArrayLike

#: modules imported (by the driver before checking a spec, and by every worker) for every study:
#: put the name of a module that registers method kinds or measurements at import time here
#: (built in: the copy-tracing kind ``trace`` and its ``tracing`` measurement)
PLUGIN_MODULES: list = ["meshmark.study.trace_kind"]


@dataclass
class Marked:
    """What a kind's ``embed`` returns: marked vertices and the bits they carry."""
    V: np.ndarray                 # (n, 3) float64 marked vertices (same vertex order and faces)
    bits: np.ndarray              # (n_bits,) 0/1 the embedded bits
    capacity: int                 # what the method offered (bins, embeddable pairs, ...)
    carried: bool | None = None   # the mark reads back exactly from the unattacked marked mesh
    info: dict = field(default_factory=dict)   # anything else (JSON-able): kept in the store


@dataclass
class Read:
    """What a kind's ``extract`` returns (the built-in measurements read these fields)."""
    bits: np.ndarray
    nc: float
    cdr: float
    correlation: float
    matches: int
    n_bits: int
    p_false_alarm: float
    detected: bool
    message_ok: bool

    @classmethod
    def compare(cls, sent: ArrayLike, got: ArrayLike, p_threshold: float | None = None) -> "Read":
        """The read-back figures of ``got`` against ``sent`` (0/1 arrays of one length); detected when
        P(false alarm) (metrics.false_alarm_probability) < p_threshold (default the framework's 1e-6).

        ``sent``, ``got``: (k,) arrays."""
        from ..metrics import correlation, false_alarm_probability, normalized_correlation
        from ..watermark.framework import DETECTION_THRESHOLD
        p_threshold = DETECTION_THRESHOLD if p_threshold is None else p_threshold
        sent = np.asarray(sent).astype(np.int64).ravel()
        got = np.asarray(got).astype(np.int64).ravel()
        if sent.shape != got.shape:
            raise MeshError(f"read {got.size} bits, expected {sent.size}")
        n = int(sent.size)
        m = int((sent == got).sum())
        p = false_alarm_probability(m, n)
        return cls(bits=got, nc=normalized_correlation(sent, got), cdr=m / n if n else 0.0,
                   correlation=correlation(sent, got), matches=m, n_bits=n, p_false_alarm=p,
                   detected=bool(p < p_threshold), message_ok=bool(m == n))


@dataclass
class MethodKind:
    name: str
    defaults: dict                # parameter -> default: the parameters a spec may set
    embed: Callable               # (mesh, params, seed, spec) -> Marked
    extract: Callable             # (attacked mesh, Marked, params) -> Read
    check: Callable | None = None  # (params) -> None, MeshError on a bad value (run at planning time)
    description: str = ""

    def full(self, params: dict) -> dict:
        return {**self.defaults, **params}


METHOD_KINDS: dict = {}


def register_method_kind(name: str, *, defaults: dict, embed: Callable, extract: Callable,
                         check: Callable | None = None, description: str = "") -> MethodKind:
    """Register a method kind for study specs (``[[methods]] name = NAME``).

    ``defaults``: every parameter the kind takes and its default (a spec's ``params`` / ``grid`` /
    ``random`` may set only these; they reach ``embed`` and ``extract`` merged over the defaults).
    ``embed(mesh, params, seed, spec) -> Marked`` and ``extract(attacked_mesh, marked, params) -> Read``
    (an ``embed`` that also takes ``store=`` gets the study's :class:`~meshmark.study.Store` or None,
    to keep expensive work of its own, as the ``trace`` kind keeps its issued copies)
    must be pure functions of their arguments (the task key is a hash of mesh, name, params, seed and
    attack: whatever runs a task must get the same row). Raise :class:`~meshmark.MeshError` when the
    mesh cannot carry the mark (the task's status becomes ``mesh_error``, not retried).
    ``check(params)`` runs once per variant when the spec is loaded (MeshError names the TOML line).
    A name of a framework method cannot be taken. Returns the :class:`MethodKind`.
    """
    from ..watermark import framework
    if name in framework.METHODS or name == "none":
        raise ValueError(f"method kind {name!r}: the name is a framework method (or 'none')")
    k = MethodKind(name, dict(defaults), embed, extract, check, description or (embed.__doc__ or "").strip())
    METHOD_KINDS[name] = k
    return k


def load_plugins(modules=()):
    import importlib
    for mod in list(PLUGIN_MODULES) + list(modules):
        importlib.import_module(mod)


# --- the thesis' own uses of Cho's and Yang's methods (raw bits, no key) -----------------------------

MESSAGES = ("random", "balanced")


def message(n: int, seed: int, kind: str = "random") -> np.ndarray:
    """The ``n`` message bits of a task: ``default_rng(seed).integers(0, 2, n)`` (``random``, as
    examples/radial_robustness.py), or a random permutation of n/2 zeros and n/2 ones
    (``balanced``, as examples/steganalysis_table.py)."""
    rng = np.random.default_rng(seed)
    if kind == "balanced":
        return rng.permutation(np.repeat([0, 1], n // 2))
    return rng.integers(0, 2, n)


def _check_common(p: dict):
    n = p.get("n_bits")
    if not (n == "all" or (isinstance(n, int) and not isinstance(n, bool) and n >= 1)):
        raise MeshError(f"n_bits must be an integer >= 1 (or \"all\" for radial-bits), got {n!r}")
    if p.get("message") not in MESSAGES:
        raise MeshError(f"message must be one of {', '.join(MESSAGES)}, got {p.get('message')!r}")
    if p["message"] == "balanced" and isinstance(n, int) and n % 2:
        raise MeshError(f"a balanced message needs an even n_bits, got {n}")


_CHO_KW = ("K", "alpha", "delta_k", "guard", "center_iters", "k_max")


def _cho_kind(kind: str):
    defaults = {"n_bits": 64, "message": "random", "K": None, "alpha": None, "delta_k": 0.001, "guard": 0.0,
                "center_iters": 0, "k_max": 100.0}

    def check(params):
        p = {**defaults, **params}
        _check_common(p)
        if p["n_bits"] == "all":
            raise MeshError("n_bits = \"all\" is for radial-bits; Cho's methods take one bit per bin")
        for k in ("alpha", "delta_k", "guard", "k_max"):
            v = p[k]
            if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise MeshError(f"{k} must be a finite number >= 0, got {v!r}")

    def embed(mesh, params, seed, spec):
        """Cho's method as published (cho.embed_bits: bins = bits unless K is given, no key)."""
        from ..watermark import cho
        p = {**defaults, **params}
        bits = message(p["n_bits"], seed, p["message"])
        kw = {k: p[k] for k in _CHO_KW}
        V, info = cho.embed_bits(mesh.V, mesh.triangles, bits, method=kind, **kw)
        got = cho.extract_bits(V, mesh.triangles, len(bits), method=kind, K=p["K"])[0]
        carried = not info.get("failed_bins") and bool(np.array_equal(got, bits))
        return Marked(V=np.asarray(V, np.float64), bits=bits, capacity=int(p["K"] or len(bits)), carried=carried,
                      info={"failed_bins": len(info.get("failed_bins") or [])})

    def extract(mesh, marked, params):
        from ..watermark import cho
        p = {**defaults, **params}
        got = cho.extract_bits(mesh.V, mesh.triangles, len(marked.bits), method=kind, K=p["K"])[0]
        return Read.compare(marked.bits, got)

    register_method_kind(f"cho-{kind}-bits", defaults=defaults, embed=embed, extract=extract, check=check,
                         description=f"Cho's {kind} method in the thesis' use: raw bits, one per bin, no key")


def radial_capacity(V, F, K: int = 400, origin_mode: str = "axis") -> int:
    """Embeddable pairs at K (eq. 6.1.4): the length of §6.1.2's full message (a bit in every pair)."""
    from ..watermark import radial
    _, ca, cb = radial.pair_counts(radial.extract_bits(V, F, 1, K=K, origin_mode=origin_mode)[1], K)
    return int(((ca + cb) >= 1).sum())


def _radial_kind():
    defaults = {"n_bits": 64, "message": "random", "K": 400, "n_thr": None, "origin_mode": "axis",
                "origin_iters": 0}

    def check(params):
        p = {**defaults, **params}
        _check_common(p)
        if not (isinstance(p["K"], int) and p["K"] >= 2):
            raise MeshError(f"K must be an integer >= 2, got {p['K']!r}")

    def embed(mesh, params, seed, spec):
        """Yang's radial method as published (radial.embed_bits: bit n in embeddable pair n, no key)."""
        from ..watermark import radial
        p = {**defaults, **params}
        F = mesh.triangles
        cap = radial_capacity(mesh.V, F, p["K"], p["origin_mode"])
        n = cap if p["n_bits"] == "all" else p["n_bits"]
        if n < 1:
            raise MeshError(f"the mesh offers no embeddable pair at K = {p['K']}")
        bits = message(n, seed, p["message"])
        V, _ = radial.embed_bits(mesh.V, F, bits, K=p["K"], n_thr=p["n_thr"], origin_mode=p["origin_mode"],
                                 origin_iters=p["origin_iters"])
        got = radial.extract_bits(V, F, n, K=p["K"], origin_mode=p["origin_mode"])[0]
        return Marked(V=np.asarray(V, np.float64), bits=bits, capacity=cap, carried=bool(np.array_equal(got, bits)))

    def extract(mesh, marked, params):
        from ..watermark import radial
        p = {**defaults, **params}
        got = radial.extract_bits(mesh.V, mesh.triangles, len(marked.bits), K=p["K"], origin_mode=p["origin_mode"])[0]
        return Read.compare(marked.bits, got)

    register_method_kind("radial-bits", defaults=defaults, embed=embed, extract=extract, check=check,
                         description="Yang's radial method in the thesis' use: raw bits, one per embeddable pair, no key")


_cho_kind("mean")
_cho_kind("variance")
_radial_kind()
