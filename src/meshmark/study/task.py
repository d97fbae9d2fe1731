"""What a worker does: run a chunk of tasks of one mesh (load once, embed once per method and seed).

A task is ``(key, mesh index, method index, seed index, attack index, attempt)`` against a
:class:`~meshmark.study.spec.Spec`. Its row is a pure function of the spec entries and the seed
(timings and the worker name aside): the payload is ``payload_bits`` bits drawn by
``numpy.random.default_rng(seed)`` (fewer when the mesh offers fewer carriers: ``capacity - 16``),
the key is ``study.key`` with ``{seed}`` filled in, random attacks get ``seed + step`` (step = the
position in a chain). A :class:`~meshmark.MeshError` (the mesh cannot carry the mark, an attack
leaves too few triangles, ...) is a result (``status = "mesh_error"``); any other exception is a
failure (``status = "error"``), retried once by the engine.
"""
from __future__ import annotations

import inspect
import json
import os
import socket
import time
import traceback

import numpy as np

from .._core import MeshError
from ..mesh import Mesh
from . import deform
from .meshes import BUILTINS, builtin_mesh, compact, load_mesh  # noqa: F401  (the worker's mesh loading)
from .measure import MEASUREMENTS, Context, load_plugins

def apply_attack(variant, mesh: Mesh, seed: int):
    """(attacked mesh, mesh to measure): with ``undo`` the similarity / rotation / reordering is undone
    for the distortion measures (what remains is the round-off of the round trip)."""
    from .. import attacks as A
    m = mesh
    if variant.undo:
        (name, p), = variant.chain
        if name == "similarity":
            p = {"seed": seed, **p}
            out, R, s, t = A.similarity(mesh, return_transform=True, **p)
            return out, Mesh.from_polygons((out.V - t) @ R / s, out.face_indices, out.face_offsets, validate=False)
        if name == "rotate":
            out = A.rotate(mesh, **p)
            return out, A.rotate(out, **{**p, "angle": -p.get("angle", 30.0)})
        if name == "reorder":
            p = {"seed": seed, **p}
            out, vp, fp = A.reorder(mesh, return_permutations=True, **p)
            return out, Mesh.from_polygons(out.V[np.argsort(vp)], mesh.face_indices, mesh.face_offsets, validate=False)
    from ..attacks.chain import step_seed
    for j, (name, p) in enumerate(variant.chain):  # the rule of meshmark.attacks.chain: step j gets seed + j
        if name in A.ATTACKS:
            m = A.ATTACKS[name](m, **step_seed(name, p, seed, j))
        else:
            m = deform.apply(name, m, p, seed + j)
    return m, m


def make_payload(cap: int, bits: int, seed: int):
    """A random payload of ``bits`` bits, or fewer: as many as ``cap`` carriers take with the
    keyed-check code (:func:`meshmark.watermark.coding.max_data_bits`)."""
    from ..watermark.coding import max_data_bits
    from ..watermark.payload import Payload
    nb = min(bits, max_data_bits(cap))
    if nb < 1:
        raise MeshError(f"the mesh offers {cap} carrier bits: too few for one payload bit with its check bits")
    rng = np.random.default_rng(seed)
    return Payload.from_bits(rng.integers(0, 2, nb))


class Worker:
    """Runs chunks against one spec (kept per process: built once, reused for every chunk)."""

    def __init__(self, spec, store_root: str | None = None):
        load_plugins(getattr(spec, "plugins", ()))
        self.spec = spec
        self.store = None
        if store_root:
            from .store import Store
            self.store = Store(store_root)
        self.name = f"{socket.gethostname()}:{os.getpid()}"

    def embed(self, mesh: Mesh, digest: str, mv, seed: int):
        from ..watermark import framework, Keyfile
        from .model import embed_key
        from .kinds import METHOD_KINDS, Marked
        sp = self.spec
        ek = embed_key(digest, mv, seed, sp) if self.store is not None else None
        kind = METHOD_KINDS.get(mv.name)
        if kind is not None:  # a registered kind (raw bits, ...): its own embed, no keyfile
            hit = self.store.get(ek) if ek is not None else None
            if hit is not None:
                m = hit.meta
                return Marked(V=hit.mesh.V, bits=np.asarray(m["bits"], np.int64), capacity=int(m["capacity"]),
                              carried=m.get("carried"), info=dict(m.get("info", {})))
            takes_store = "store" in inspect.signature(kind.embed).parameters  # kinds that keep work of their own
            r = (kind.embed(mesh, kind.full(mv.params), seed, sp, store=self.store) if takes_store else
                 kind.embed(mesh, kind.full(mv.params), seed, sp))
            if ek is not None:
                self.store.put(ek, mesh.with_vertices(r.V), bits=[int(b) for b in r.bits], capacity=int(r.capacity),
                               carried=r.carried, info=r.info, method=mv.name, params=mv.params, seed=seed,
                               mesh_digest=digest)
            return r
        if ek is not None:
            hit = self.store.get(ek)
            if hit is not None:
                kf = Keyfile.from_dict(hit.meta["keyfile"])
                return framework.EmbedResult(V=hit.mesh.V, keyfile=kf, capacity=int(hit.meta["capacity"]),
                                             stats=dict(hit.meta.get("stats", {})))
        # the carriers the method's parameters offer to a payload of payload_bits bits (params="auto":
        # the rung chosen for it, or the largest rung if it does not fit; the payload is then shortened)
        cap = framework.capacity(mesh, method=mv.name, weld=sp.weld, n_data=sp.payload_bits, **mv.params)
        if sp.payload is not None:  # a fixed text message
            from ..watermark.payload import Payload
            payload = Payload.coerce(sp.payload)
        else:
            payload = make_payload(cap, sp.payload_bits, seed)
        r = framework.embed(mesh, payload=payload, key=sp.key.format(seed=seed), method=mv.name, weld=sp.weld,
                            **mv.params)
        if ek is not None:
            kfd = r.keyfile.to_dict()
            kfd["created"] = ""  # content-addressed: no wall-clock time in the stored object
            self.store.put(ek, mesh.with_vertices(r.V), keyfile=kfd, capacity=int(r.capacity),
                           stats={k: v for k, v in r.stats.items() if isinstance(v, (int, float, str, bool))},
                           method=mv.name, params=mv.params, seed=seed, mesh_digest=digest)
        return r

    def run_chunk(self, tasks, digests: dict, mesh_bytes: bytes | None = None) -> list:
        """Rows for ``tasks`` (all of one mesh). Never raises for a task: errors go into the row."""
        sp = self.spec
        rows = []
        mi = tasks[0][1]
        label, path = sp.meshes[mi]
        t0 = time.perf_counter()
        try:
            mesh = load_mesh(path, mesh_bytes, sp.compact)
            load_err = None
        except Exception as e:  # noqa: BLE001 - reported in every row of the chunk
            mesh, load_err = None, e
        t_load = time.perf_counter() - t0
        embeds: dict = {}
        first = True
        for key, mi2, vi, si, ai, attempt in tasks:
            assert mi2 == mi, "a chunk holds one mesh"
            mv, av, seed = sp.methods[vi], sp.attacks[ai], sp.seeds[si]
            row = {"key": key, "mesh": label, "mesh_digest": digests[mi], "method": mv.label, "method_name": mv.name,
                   "method_params": json.dumps(mv.params, sort_keys=True), "attack": av.label,
                   "attack_chain": json.dumps([[n, p] for n, p in av.chain], sort_keys=True),
                   "attack_level": av.level, "seed": seed, "attempt": attempt, "worker": self.name,
                   "status": "ok", "error": None}
            tm = {"t_load": t_load if first else 0.0, "t_embed": 0.0, "t_attack": 0.0, "t_extract": 0.0,
                  "t_measure": 0.0}
            first = False
            ts = time.perf_counter()
            try:
                if load_err is not None:
                    raise load_err
                row["mesh_vertices"], row["mesh_faces"] = mesh.n_vertices, mesh.n_faces
                emb = None
                if mv.name != "none":
                    ek = (vi, si)
                    if ek not in embeds:
                        te = time.perf_counter()
                        try:
                            embeds[ek] = (self.embed(mesh, digests[mi], mv, seed), None)
                        except Exception as e:  # noqa: BLE001 - the same outcome for every attack
                            embeds[ek] = (None, e)
                        tm["t_embed"] = time.perf_counter() - te
                    emb, err = embeds[ek]
                    if err is not None:
                        raise err
                marked = mesh.with_vertices(emb.V) if emb is not None else None
                ta = time.perf_counter()
                attacked, measured = apply_attack(av, marked if marked is not None else mesh, seed)
                tm["t_attack"] = time.perf_counter() - ta
                row["n_vertices"], row["n_faces"] = attacked.n_vertices, attacked.n_faces
                ctx = Context(original=mesh, attacked=attacked, measured=measured, marked=marked, embed=emb,
                              seed=seed, distance_seed=sp.distance_seed,
                              distance_samples=sp.distance_samples, timings=tm, method=mv)
                if emb is not None:
                    ctx.extract()
                tmz = time.perf_counter()
                for name in sp.measurements:
                    ms = MEASUREMENTS[name]
                    if emb is None and ms.needs_mark:
                        continue  # attack-only task: the mark's columns stay null
                    row.update(ms.fn(ctx))
                tm["t_measure"] = time.perf_counter() - tmz
            except MeshError as e:
                row["status"], row["error"] = "mesh_error", str(e)
            except Exception as e:  # noqa: BLE001
                row["status"] = "error"
                row["error"] = f"{type(e).__name__}: {e}\n" + "".join(traceback.format_exc(limit=6))
            tm["t_task"] = time.perf_counter() - ts + tm["t_load"]
            row.update(tm)
            rows.append(row)
        return rows


_WORKER: Worker | None = None


def init_worker(spec, store_root):
    """ProcessPoolExecutor initializer: the spec is shipped once per process."""
    global _WORKER
    _WORKER = Worker(spec, store_root)


def run_chunk(tasks, digests, mesh_bytes=None):
    return _WORKER.run_chunk(tasks, digests, mesh_bytes)


_DASK_WORKERS: dict = {}


def run_chunk_dask(spec, store_root, tasks, digests, mesh_bytes=None):
    """Dask entry point: one Worker per (process, spec), cached across chunks."""
    k = (id(spec), store_root)
    w = _DASK_WORKERS.get(k)
    if w is None or w.spec is not spec:
        _DASK_WORKERS.clear()
        w = _DASK_WORKERS[k] = Worker(spec, store_root)
    return w.run_chunk(tasks, digests, mesh_bytes)
