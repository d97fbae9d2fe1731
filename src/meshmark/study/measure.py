"""The measurement registry of studies: name -> function of a task's :class:`Context` -> columns.

A measurement declares its output columns with their Arrow types, so every Parquet partition of a
study has the same schema whatever its rows hold (a column a task cannot fill is null). Add one with
:func:`register_measurement` (the steganalysis features of issue 15 plug in here)::

    @register_measurement("my_feature", {"my_value": pa.float64()}, needs_mark=False)
    def _mine(ctx):
        return {"my_value": float(some_function(ctx.attacked))}

``ctx.original`` is the mesh as loaded, ``ctx.marked`` the marked mesh (None without a method),
``ctx.attacked`` the attacked mesh, ``ctx.measured`` the attacked mesh with a similarity / rotation /
reordering undone when the attack says ``undo = true`` (else the attacked mesh), ``ctx.reference``
the marked mesh (or the original), ``ctx.embed`` the EmbedResult (a :class:`~meshmark.study.kinds.Marked`
for a registered method kind, with its ``bits``) and ``ctx.extract()`` the ExtractResult (a
:class:`~meshmark.study.kinds.Read` for a kind; computed once, on the attacked mesh), ``ctx.method``
the MethodVariant (``name``, ``params``, ``label``) and ``ctx.seed`` the task's seed. A measurement that must run in the worker that
loaded the module is registered at import time of a module listed in ``MEASUREMENT_MODULES``.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import pyarrow as pa

from .. import metrics as M
from typing import Any


@dataclass
class Measurement:
    name: str
    columns: dict                 # column -> pyarrow DataType
    fn: Callable
    needs_mark: bool = False
    description: str = ""


MEASUREMENTS: dict = {}
#: modules imported by :func:`load_plugins` (in the driver and in every worker) to register more measurements
MEASUREMENT_MODULES: list = []
DEFAULT = ["nc", "cdr", "detection", "message", "capacity", "rmse"]


def register_measurement(name: str, columns: dict, needs_mark: bool = False,
                         description: str = "") -> Callable[[Callable[..., dict[str, Any]]],
                                                            Callable[..., dict[str, Any]]]:
    """Decorator: register ``fn(ctx) -> dict`` under ``name`` with its declared ``columns``."""
    def deco(fn):
        MEASUREMENTS[name] = Measurement(name, dict(columns), fn, needs_mark, description or (fn.__doc__ or "").strip())
        return fn
    return deco


def load_plugins(modules=()):
    """Import MEASUREMENT_MODULES, kinds.PLUGIN_MODULES and ``modules`` (a spec's ``plugins``)."""
    from .kinds import load_plugins as _kinds
    for mod in MEASUREMENT_MODULES:
        importlib.import_module(mod)
    _kinds(modules)


@dataclass
class Context:
    original: object
    attacked: object
    measured: object
    marked: object = None
    embed: object = None
    seed: int = 0
    distance_seed: int = 0
    distance_samples: int | None = None
    timings: dict = field(default_factory=dict)
    method: object = None         # the MethodVariant
    _extract: object = None

    @property
    def reference(self):
        return self.marked if self.marked is not None else self.original

    def extract(self):
        if self.embed is None:
            return None
        if self._extract is None:
            import time
            from ..watermark import framework
            from .kinds import METHOD_KINDS, Marked
            t0 = time.perf_counter()
            if isinstance(self.embed, Marked):
                kind = METHOD_KINDS[self.method.name]
                self._extract = kind.extract(self.attacked, self.embed, kind.full(self.method.params))
            else:
                self._extract = framework.extract(self.attacked, keyfile=self.embed.keyfile)
            self.timings["t_extract"] = time.perf_counter() - t0
        return self._extract


def _same_faces(a, b) -> bool:
    return (a.n_vertices == b.n_vertices and np.array_equal(a.face_offsets, b.face_offsets)
            and np.array_equal(a.face_indices, b.face_indices))


@register_measurement("nc", {"nc": pa.float64()}, needs_mark=True)
def _nc(ctx):
    """Normalized correlation of the coded bits (framework.extract)."""
    return {"nc": ctx.extract().nc}


@register_measurement("cdr", {"cdr": pa.float64()}, needs_mark=True)
def _cdr(ctx):
    """Correct detection rate of the coded bits."""
    return {"cdr": ctx.extract().cdr}


@register_measurement("detection", {"detected": pa.bool_(), "p_false_alarm": pa.float64(), "matches": pa.int64(),
                                    "n_bits": pa.int64()}, needs_mark=True)
def _detection(ctx):
    """Detection decision (P(false alarm) < 1e-6), the probability, matching and coded bits."""
    x = ctx.extract()
    return {"detected": bool(x.detected), "p_false_alarm": float(x.p_false_alarm), "matches": int(x.matches),
            "n_bits": int(x.n_bits)}


@register_measurement("message", {"message_ok": pa.bool_()}, needs_mark=True)
def _message(ctx):
    """Whether the framed message came back (its length and CRC-8 agree)."""
    return {"message_ok": bool(ctx.extract().message_ok)}


@register_measurement("capacity", {"capacity": pa.int64(), "payload_bits": pa.int64()}, needs_mark=True)
def _capacity(ctx):
    """Carrier bits the method found, and the payload bits embedded."""
    e = ctx.embed
    nb = len(e.bits) if hasattr(e, "bits") else e.keyfile.payload["n_bits"]
    return {"capacity": int(e.capacity), "payload_bits": int(nb)}


@register_measurement("correlation", {"correlation": pa.float64()}, needs_mark=True)
def _correlation(ctx):
    """C of eq. 6.3.11 (Pearson correlation of the +-1 sequences) of the embedded and read bits: for
    the raw-bits kinds (cho-mean-bits, radial-bits, ...; null for framework methods, whose ``nc`` is
    the normalized correlation of the coded bits)."""
    return {"correlation": getattr(ctx.extract(), "correlation", None)}


@register_measurement("carried", {"carried": pa.bool_()}, needs_mark=True)
def _carried(ctx):
    """Whether the mark reads back exactly from the unattacked marked mesh (and, for Cho, no bin
    failed): the "can carry the mark" of Table 6.2. Registered kinds only (null for framework methods)."""
    return {"carried": getattr(ctx.embed, "carried", None)}


@register_measurement("rmse", {"rmse_rel": pa.float64(), "embed_rmse_rel": pa.float64()})
def _rmse(ctx):
    """Vertex RMSE / bbox diagonal of the reference: attacked (undone) vs reference when the faces are
    the same (else null), and marked vs original (embedding distortion, null without a method)."""
    ref, meas = ctx.reference, ctx.measured
    out = {"rmse_rel": None, "embed_rmse_rel": None}
    if _same_faces(ref, meas):
        out["rmse_rel"] = M.vertex_rmse(ref, meas) / M.bbox_diagonal(ref)
    if ctx.marked is not None:
        out["embed_rmse_rel"] = M.vertex_rmse(ctx.original, ctx.marked) / M.bbox_diagonal(ctx.original)
    return out


@register_measurement("hausdorff", {"hausdorff_rel": pa.float64(), "rms_rel": pa.float64()})
def _hausdorff(ctx):
    """Symmetric Hausdorff (bounded within 1 %) and Metro RMS distance, relative to the reference's
    bbox diagonal (metrics.surface_distance, seed = study.distance_seed, area samples =
    study.distance_samples, default 2 x triangles)."""
    d = M.surface_distance(ctx.reference, ctx.measured, seed=ctx.distance_seed, n_samples=ctx.distance_samples)
    return {"hausdorff_rel": d["hausdorff_rel"], "rms_rel": d["rms_rel"]}


@register_measurement("normal_degradation", {"normal_deg_mean": pa.float64(), "normal_deg_area": pa.float64()})
def _normals(ctx):
    """dis^av of eq. 3.2.2 (mean and area weights, degrees) when the faces are the same, else null."""
    ref, meas = ctx.reference, ctx.measured
    if not _same_faces(ref, meas):
        return {"normal_deg_mean": None, "normal_deg_area": None}
    return {"normal_deg_mean": M.normal_degradation(ref, meas, weighting="mean", degrees=True),
            "normal_deg_area": M.normal_degradation(ref, meas, weighting="area", degrees=True)}


@register_measurement("cho_steganalysis", {"stega_k": pa.int64(), "stega_d": pa.float64(), "stega_marked": pa.bool_()})
def _stega(ctx):
    """The §6.4 steganalyzer on the attacked mesh: K', D_K' and the marked decision (K in 1..200)."""
    from ..steganalysis import cho as S
    r = S.analyze(ctx.attacked, K_min=1, K_max=200)
    return {"stega_k": int(r["k_estimate"]), "stega_d": float(r["bhattacharyya"]), "stega_marked": bool(r["marked"])}


@register_measurement("features", {"features": pa.list_(pa.float64())})
def _features(ctx):
    """A steganalysis feature vector of the attacked mesh: ``meshmark.steganalysis.features.extract``
    if that module exists (issue 15), else the §6.4 curve D_K for K = 1..64 (-inf where skipped)."""
    try:
        from ..steganalysis import features as Fx  # noqa: F401
        return {"features": [float(x) for x in np.ravel(Fx.extract(ctx.attacked))]}
    except ImportError:
        from ..steganalysis import cho as S
        return {"features": [float(x) for x in S.analyze(ctx.attacked, K_min=1, K_max=64)["D"]]}


#: timing columns (seconds), always written, excluded when results are compared
TIMINGS = {"t_load": pa.float64(), "t_embed": pa.float64(), "t_attack": pa.float64(), "t_extract": pa.float64(),
           "t_measure": pa.float64(), "t_task": pa.float64()}
