"""The ``trace`` method kind of studies: copy tracing (meshmark.watermark.tracing) under attack.

A task of this kind is one trial of a leak: the asset's N copies (``n_copies``, default 100) are
issued once with :func:`meshmark.watermark.tracing.issue` (default settings: ``method``, ``params``),
copy number ``seed mod N`` (counted from 0: copy ``0001`` for seed 0) is the leaked one, the task's
attack is applied to it and :func:`meshmark.watermark.tracing.trace` is asked whose copy it is. The
``tracing`` measurement records the copy named (or none), the right copy, the outcome (``right``,
``wrong``, ``none``) and the false-alarm probability.

``informed = true`` passes the original (the unmarked asset) to ``trace(..., original=...)``; when
this meshmark's ``trace`` takes no ``original`` (checked with :func:`inspect.signature`), nothing is
issued or traced and the rows say ``trace_informed = "unavailable"`` with a null outcome.

Issuing is done once per asset and kept: with ``study.store = true`` under ``OUT/store/tracing/<id>/``
(``registry.sqlite``, ``original.npz`` and the copies the spec's seeds use, ``<copy>.npz``), so every
worker, every later task and a resumed run use the same copies; without the store, once per worker
process in a temporary folder (the codewords are fresh random numbers of ``secrets``, so the rows then
depend on which process ran them). ``<id>`` is a hash of the mesh, the method, its parameters, N, the
copies used and the meshmark version.
"""
from __future__ import annotations

import atexit
import hashlib
import inspect
import json
import os
import pathlib
import shutil
import tempfile
from dataclasses import dataclass

import numpy as np
import pyarrow as pa

from .._core import MeshError
from ..mesh import Mesh
from .kinds import Marked, Read, register_method_kind
from .measure import register_measurement

KEY = "meshmark-study-trace"   # the owner's key of every issued asset (the copies are the study's own)
DEFAULTS = {"method": "laplacian", "n_copies": 100, "informed": False, "params": "auto"}
_METHODS = ("laplacian", "cho-mean", "cho-variance", "radial")
_ISSUED: dict = {}             # asset id -> folder (this process)
_TMP: list = []


@dataclass
class TraceRead(Read):
    """A :class:`Read` with the trace's own answer (None when informed tracing is unavailable)."""
    trace: dict | None = None
    right_copy: str | None = None
    informed: str = "no"


def informed_available() -> bool:
    """Does this meshmark's :func:`tracing.trace` take the original (informed tracing)?"""
    from ..watermark import tracing
    return "original" in inspect.signature(tracing.trace).parameters


def _check(params):
    p = {**DEFAULTS, **params}
    if p["method"] not in _METHODS:
        raise MeshError(f"trace method must be one of {', '.join(_METHODS)}, got {p['method']!r}")
    n = p["n_copies"]
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 100_000:
        raise MeshError(f"n_copies must be an integer in 1..100000, got {n!r}")
    if not isinstance(p["informed"], bool):
        raise MeshError(f"informed must be true or false, got {p['informed']!r}")
    if p["params"] not in ("auto", "thesis"):
        raise MeshError(f"params must be auto or thesis, got {p['params']!r}")


def _save(path: pathlib.Path, V, mesh: Mesh):
    np.savez(path, V=np.ascontiguousarray(V, np.float64), face_indices=mesh.face_indices, face_offsets=mesh.face_offsets)


def _load(path: pathlib.Path) -> Mesh:
    with np.load(path) as z:
        return Mesh.from_polygons(z["V"], z["face_indices"], z["face_offsets"], validate=False)


def _tmp_root() -> pathlib.Path:
    if not _TMP:
        d = tempfile.mkdtemp(prefix="meshmark-trace-")
        _TMP.append(d)
        atexit.register(shutil.rmtree, d, True)
    return pathlib.Path(_TMP[0])


def _issued(mesh: Mesh, p: dict, picks: list, store) -> pathlib.Path:
    """The folder of the asset's issued copies (issued now if no worker did yet)."""
    from .. import __version__
    from ..watermark import tracing
    ident = {"mesh": tracing.source_digest(mesh), "method": p["method"], "params": p["params"], "n": p["n_copies"],
             "picks": picks, "key": KEY, "meshmark": __version__}
    aid = hashlib.blake2b(json.dumps(ident, sort_keys=True).encode(), digest_size=16).hexdigest()
    root = (pathlib.Path(store.root) / "tracing") if store is not None else _tmp_root()
    final = root / aid
    if (final / "done.json").is_file():
        return final
    root.mkdir(parents=True, exist_ok=True)
    tmp = pathlib.Path(tempfile.mkdtemp(dir=root, prefix=f".tmp-{aid[:8]}-"))
    try:
        out = tracing.issue(mesh, key=KEY, registry=tmp / "registry.sqlite", n_copies=p["n_copies"],
                            method=p["method"], params=p["params"], source_name="study")
        ids = [cid for cid, _ in out]
        for i in picks:
            _save(tmp / f"{ids[i]}.npz", out[i][1], mesh)
        _save(tmp / "original.npz", mesh.V, mesh)
        (tmp / "done.json").write_text(json.dumps({**ident, "ids": ids}))
        try:
            os.rename(tmp, final)
        except OSError:  # another worker finished first: use its copies
            shutil.rmtree(tmp, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return final


def _embed(mesh, params, seed, spec, store=None):
    """Issue the asset's copies once; this task's leaked copy is number ``seed mod n_copies``."""
    from ..watermark import tracing
    p = {**DEFAULTS, **params}
    if p["informed"] and not informed_available():
        return Marked(V=np.array(mesh.V, np.float64), bits=np.zeros(0, np.int64), capacity=0, carried=None,
                      info={"informed": "unavailable"})
    n = p["n_copies"]
    # the copies kept: those of the spec's seeds and of seeds 0, 1, 2 (so a 1-seed run and a 3-seed
    # run of the same spec share their issued copies)
    picks = sorted({int(s) % n for s in list(getattr(spec, "seeds", [])) + [0, 1, 2, int(seed)]})
    folder = _issued(mesh, p, picks, store)
    ids = json.loads((folder / "done.json").read_text())["ids"]
    cid = ids[int(seed) % n]
    copy = _load(folder / f"{cid}.npz")
    with tracing.Registry(folder / "registry.sqlite", create=False) as reg:
        (asset_id, _, C), = reg.assets()
        cids, W = reg.codewords(asset_id, C)
    bits = W[cids.index(cid)].astype(np.int64)
    r = _trace(copy, folder, p["informed"])
    return Marked(V=np.array(copy.V), bits=bits, capacity=int(C), carried=bool(r.get("copy") == cid),
                  info={"folder": str(folder), "copy": cid, "n_copies": n, "informed": "yes" if p["informed"] else "no"})


def _trace(mesh, folder: pathlib.Path, informed: bool) -> dict:
    from ..watermark import tracing
    kw = {"original": _load(folder / "original.npz")} if informed else {}
    return tracing.trace(mesh, registry=str(folder / "registry.sqlite"), **kw)


def _extract(mesh, marked, params):
    info = marked.info
    if info.get("informed") == "unavailable":
        return TraceRead(bits=np.zeros(0, np.int64), nc=0.0, cdr=0.0, correlation=0.0, matches=0, n_bits=0,
                         p_false_alarm=1.0, detected=False, message_ok=False, trace=None, informed="unavailable")
    r = _trace(mesh, pathlib.Path(info["folder"]), info["informed"] == "yes")
    C = int(r.get("n_carriers") or 0)
    m = int(r.get("matches") or 0)
    cdr = m / C if C else 0.0
    return TraceRead(bits=np.zeros(0, np.int64), nc=2 * cdr - 1, cdr=cdr, correlation=2 * cdr - 1, matches=m, n_bits=C,
                     p_false_alarm=float(r["p_false_alarm"]), detected=bool(r["detected"]),
                     message_ok=bool(r.get("copy") == info["copy"]), trace=r, right_copy=info["copy"],
                     informed=info["informed"])


register_method_kind("trace", defaults=DEFAULTS, embed=_embed, extract=_extract, check=_check,
                     description="copy tracing: N copies issued once, one attacked per trial, traced")


@register_measurement("tracing", {"trace_copy": pa.string(), "trace_right_copy": pa.string(),
                                  "trace_outcome": pa.string(), "trace_p": pa.float64(),
                                  "trace_informed": pa.string(), "trace_n_copies": pa.int64()}, needs_mark=True)
def _tracing(ctx):
    """Copy tracing (the ``trace`` kind; null for other methods): the copy named (null: none), the
    attacked copy, the outcome right / wrong / none, P(false alarm), informed yes / no / unavailable."""
    x = ctx.extract()
    if not isinstance(x, TraceRead):
        return {"trace_copy": None, "trace_right_copy": None, "trace_outcome": None, "trace_p": None,
                "trace_informed": None, "trace_n_copies": None}
    if x.trace is None:
        return {"trace_copy": None, "trace_right_copy": None, "trace_outcome": None, "trace_p": None,
                "trace_informed": x.informed, "trace_n_copies": None}
    named = x.trace.get("copy")
    outcome = "none" if named is None else "right" if named == x.right_copy else "wrong"
    return {"trace_copy": named, "trace_right_copy": x.right_copy, "trace_outcome": outcome,
            "trace_p": float(x.trace["p_false_alarm"]), "trace_informed": x.informed,
            "trace_n_copies": int(x.trace.get("n_copies") or 0)}
