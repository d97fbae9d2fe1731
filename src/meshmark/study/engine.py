"""Running a study: plan, skip finished keys, run chunks on a process pool or Dask, write Parquet.

Results live under ``OUT/results/part-<run>-<n>.parquet``: one partition per finished chunk, written
to a temporary name and renamed, so a killed run leaves only whole partitions and at most the chunks
in flight are lost. :func:`load_results` reads them all and keeps one row per key (an ``ok`` or
``mesh_error`` row over an ``error`` row, then the latest attempt).

Execution:

* ``workers`` (default ``os.cpu_count()``): a :class:`concurrent.futures.ProcessPoolExecutor` (spawned
  processes; the spec is shipped once per process by the initializer); ``workers=0`` runs in the
  calling process (debugging, profiling);
* ``dask="local:N"``: a :class:`distributed.LocalCluster` of N single-threaded worker processes;
  ``dask="tcp://host:8786"``: a running scheduler. The spec is scattered once to every worker; with
  ``ship_meshes`` each chunk carries its mesh file's bytes (workers without the shared path).

A task that raises anything but MeshError (or whose worker dies) is recorded with its error and
submitted once more (``retries=1``); if it fails again it is reported, and the study goes on.
"""
from __future__ import annotations

import importlib
import json
import os
import pathlib
import sys
import time
import uuid
from concurrent.futures import FIRST_COMPLETED, CancelledError, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from .._core import MeshError
from .measure import MEASUREMENTS, TIMINGS, load_plugins
from .expansion import plan
from .model import Spec
from .spec import load_spec
from . import task as T
from .._typing import PathLike
from typing import Callable
from typing import Any

BASE_COLUMNS = {
    "key": pa.string(), "mesh": pa.string(), "mesh_digest": pa.string(), "mesh_vertices": pa.int64(),
    "mesh_faces": pa.int64(), "method": pa.string(), "method_name": pa.string(), "method_params": pa.string(),
    "attack": pa.string(), "attack_chain": pa.string(), "attack_level": pa.float64(), "seed": pa.int64(),
    "n_vertices": pa.int64(), "n_faces": pa.int64(), "status": pa.string(), "error": pa.string(),
    "attempt": pa.int64(), "worker": pa.string(),
}
#: columns that depend on who ran a task and when (left out when results are compared)
VOLATILE = {"worker", "attempt"} | set(TIMINGS)
DONE = ("ok", "mesh_error")


def schema(spec: Spec) -> pa.Schema:
    cols = dict(BASE_COLUMNS)
    for m in spec.measurements:
        cols.update(MEASUREMENTS[m].columns)
    cols.update(TIMINGS)
    return pa.schema(list(cols.items()))


@dataclass
class Summary:
    planned: int = 0
    skipped: int = 0
    ran: int = 0
    ok: int = 0
    mesh_error: int = 0
    failed: int = 0
    retried: int = 0
    wall: float = 0.0
    plan_seconds: float = 0.0
    failures: list = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The summary's fields as a plain dict (task counts, seconds, failures)."""
        return dict(self.__dict__)


# --- results on disk ------------------------------------------------------------------------------

def _parts(out) -> list:
    return sorted((pathlib.Path(out) / "results").glob("part-*.parquet"))


def finished_keys(out) -> set:
    keys = set()
    for p in _parts(out):
        t = pq.read_table(p, columns=["key", "status"])
        k, s = t.column("key").to_pylist(), t.column("status").to_pylist()
        keys.update(kk for kk, ss in zip(k, s) if ss in DONE)
    return keys


def load_results(out: PathLike, volatile: bool = True) -> pa.Table:
    """Every result row under ``out`` (one per key), sorted by key; ``volatile=False`` drops the
    timing, worker and attempt columns (what two runs of a spec must agree on bit for bit)."""
    parts = _parts(out)
    if not parts:
        raise MeshError(f"{out}: no results (no results/part-*.parquet)")
    t = pa.concat_tables([pq.read_table(p) for p in parts], promote_options="default")
    keys = np.asarray(t.column("key").to_pylist(), dtype=object)
    done = np.isin(np.asarray(t.column("status").to_pylist(), dtype=object), DONE).astype(np.int64)
    attempt = np.asarray(t.column("attempt").fill_null(0).to_numpy(), dtype=np.int64)
    order = np.lexsort((attempt, done, keys))
    ks = keys[order]
    last = np.ones(len(ks), bool)
    last[:-1] = ks[1:] != ks[:-1]
    t = t.take(pa.array(order[last]))
    if not volatile:
        t = t.drop_columns([c for c in t.column_names if c in VOLATILE])
    return t


class _Writer:
    def __init__(self, out: pathlib.Path, sch: pa.Schema):
        self.dir = out / "results"
        self.dir.mkdir(parents=True, exist_ok=True)
        self.schema = sch
        self.run = time.strftime("%Y%m%dT%H%M%S") + "-" + uuid.uuid4().hex[:6]
        self.n = 0

    def write(self, rows: list):
        if not rows:
            return
        cols = {name: [r.get(name) for r in rows] for name in self.schema.names}
        table = pa.table({n: pa.array(cols[n], type=self.schema.field(n).type) for n in self.schema.names},
                         schema=self.schema)
        self.n += 1
        final = self.dir / f"part-{self.run}-{self.n:06d}.parquet"
        tmp = self.dir / f".tmp-{final.name}"
        pq.write_table(table, tmp)
        os.replace(tmp, final)


# --- progress ----------------------------------------------------------------------------------------

class _Progress:
    def __init__(self, total: int, enabled: bool | None, log):
        self.total, self.done, self.failed = total, 0, 0
        self.log = log
        self.t0 = self.last = time.monotonic()
        tty = sys.stderr.isatty() if enabled is None else enabled
        self.bar = None
        if tty and total:
            from tqdm import tqdm
            self.bar = tqdm(total=total, unit="task", smoothing=0.05, dynamic_ncols=True)

    def update(self, n: int, failed: int = 0):
        self.done += n
        self.failed += failed
        if self.bar is not None:
            self.bar.update(n)
            if failed:
                self.bar.set_postfix(failed=self.failed)
            return
        now = time.monotonic()
        if now - self.last >= 10 or self.done == self.total:
            self.last = now
            el = now - self.t0
            rate = self.done / el if el > 0 else 0.0
            eta = (self.total - self.done) / rate if rate > 0 else float("nan")
            self.log(f"[study] {self.done}/{self.total} tasks ({100 * self.done / max(self.total, 1):.1f} %), "
                     f"{rate:.2f} tasks/s, elapsed {el:.0f} s, ETA {eta:.0f} s, {self.failed} failed")

    def close(self):
        if self.bar is not None:
            self.bar.close()


# --- executors ---------------------------------------------------------------------------------------

class _Local:
    def __init__(self, spec, store_root, workers):
        self.args = (spec, store_root)
        self.workers = workers
        self.pool = None
        self._inproc = None
        self.gen = 0
        self._new()

    def _new(self):
        if self.workers == 0:
            self._inproc = T.Worker(*self.args)
            return
        import multiprocessing as mp
        self.pool = ProcessPoolExecutor(self.workers, mp_context=mp.get_context("spawn"),
                                        initializer=T.init_worker, initargs=self.args)

    def submit(self, tasks, digests, data):
        if self.pool is None:
            from concurrent.futures import Future
            f = Future()
            try:
                f.set_result(self._inproc.run_chunk(tasks, digests, data))
            except BaseException as e:  # noqa: BLE001
                f.set_exception(e)
            return f
        return self.pool.submit(T.run_chunk, tasks, digests, data)

    def wait(self, futures):
        return wait(futures, return_when=FIRST_COMPLETED)[0]

    def broken(self, exc, gen) -> None:
        """A worker process died: every chunk in flight fails with BrokenProcessPool (and is retried);
        start one new pool for the first of them."""
        if isinstance(exc, BrokenProcessPool) and gen == self.gen:
            self.pool.shutdown(wait=False, cancel_futures=True)
            self.gen += 1
            self._new()

    def close(self):
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)


class _Dask:
    def __init__(self, spec, store_root, address):
        from distributed import Client, LocalCluster
        self.cluster = None
        if address.startswith("local:"):
            n = int(address.split(":", 1)[1])
            self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                        silence_logs=40)
            self.client = Client(self.cluster)
        else:
            self.client = Client(address)
        self.spec_f = self.client.scatter(spec, broadcast=True)
        self.store_root = store_root
        self.gen = 0

    def submit(self, tasks, digests, data):
        return self.client.submit(T.run_chunk_dask, self.spec_f, self.store_root, tasks, digests, data, pure=False)

    def wait(self, futures):
        from distributed import wait as dwait
        return dwait(list(futures), return_when="FIRST_COMPLETED").done

    def broken(self, exc, gen) -> None:
        pass  # Dask reschedules lost workers' tasks itself; a task error comes back as an exception

    def close(self):
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


# --- the run ---------------------------------------------------------------------------------------

def chunks_of(spec: Spec, keys, idx, todo_mask, size: int):
    """Lists of task tuples, one mesh per chunk, at most ``size`` tasks, in plan order (so the tasks
    that share an embedding, same mesh + method + seed, stay together)."""
    sel = np.flatnonzero(todo_mask)
    out, cur, cur_mesh = [], [], -1
    for i in sel:
        mi, vi, si, ai = (int(x) for x in idx[i])
        if cur and (mi != cur_mesh or len(cur) >= size):
            out.append(cur)
            cur = []
        cur_mesh = mi
        cur.append((keys[i], mi, vi, si, ai, 1))
    if cur:
        out.append(cur)
    return out


#: Task kinds beyond the method x attack grid, chosen by a spec's top-level ``kind = "..."``:
#: name -> "module:function", called as function(raw_spec_dict, out_path, base_path, log) -> Summary.
TASK_KINDS = {"steganalysis": "meshmark.steganalysis.study:run_study"}


def task_kind(spec):
    """(runner, raw dict, base folder) when ``spec`` (path, TOML text or dict) names a registered ``kind``;
    None for an ordinary grid spec. Register a kind by adding it to :data:`TASK_KINDS`."""
    import tomllib
    if isinstance(spec, Spec):
        return None
    base = pathlib.Path.cwd()
    if isinstance(spec, dict):
        raw = spec
    else:
        s = str(spec)
        p = pathlib.Path(s) if "\n" not in s else None
        try:
            raw = tomllib.loads(p.read_text() if p is not None and p.is_file() else s)
        except (tomllib.TOMLDecodeError, OSError):
            return None  # load_spec reports it
        if p is not None and p.is_file():
            base = p.resolve().parent
    kind = raw.get("kind")
    if kind is None:
        return None
    if kind not in TASK_KINDS:
        raise MeshError(f"study spec: unknown kind {kind!r} (known: {', '.join(sorted(TASK_KINDS))})")
    mod, fn = TASK_KINDS[kind].split(":")
    return getattr(importlib.import_module(mod), fn), raw, base


def run(spec: Spec | PathLike | dict[str, Any], out: PathLike, *, workers: int | None = None,
        dask: str | None = None, progress: bool | None = None,
        retries: int = 1, ship_meshes: bool = False, chunk_size: int | None = None,
        log: Callable[[str], None] | None = None, max_tasks: int | None = None) -> Summary:
    """Run (or resume) the study ``spec`` (path, TOML text, dict or Spec) with results under ``out``."""
    log = log or (lambda s: print(s, file=sys.stderr, flush=True))
    if dask:  # before anything is planned or written
        from ..optional import require
        require("distributed", "a Dask study (--dask)")
    kind = task_kind(spec)
    if kind is not None:
        return kind[0](kind[1], pathlib.Path(out), kind[2], log)
    load_plugins()
    t0 = time.perf_counter()
    sp = spec if isinstance(spec, Spec) else load_spec(spec)
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    keys, idx, digests = plan(sp)
    done = finished_keys(out)
    todo = np.fromiter((k not in done for k in keys), bool, len(keys))
    if max_tasks is not None:
        todo[np.cumsum(todo) > max_tasks] = False
    S = Summary(planned=len(keys), skipped=int(len(keys) - todo.sum() if max_tasks is None else len(done & set(keys))))
    S.plan_seconds = time.perf_counter() - t0
    (out / "spec.json").write_text(json.dumps({"name": sp.name, "source": sp.source, "spec": sp.raw,
                                               "base": str(sp.base)}, indent=1, default=str))
    chunks = chunks_of(sp, keys, idx, todo, chunk_size or sp.chunk_size)
    n_todo = int(todo.sum())
    log(f"[study] {sp.name}: {len(keys)} tasks planned ({len(sp.meshes)} meshes x {len(sp.methods)} methods x "
        f"{len(sp.seeds)} seeds x {len(sp.attacks)} attacks), {S.skipped} already done, {n_todo} to run in "
        f"{len(chunks)} chunks" + (f" on dask {dask}" if dask else f" on {workers if workers is not None else os.cpu_count()} workers"))
    writer = _Writer(out, schema(sp))
    store_root = str(out / "store") if sp.store else None
    dig = {i: d for i, d in enumerate(digests)}
    if not chunks:
        S.wall = time.perf_counter() - t0
        return S
    ex = _Dask(sp, store_root, dask) if dask else _Local(sp, store_root, os.cpu_count() if workers is None else workers)
    bar = _Progress(n_todo, progress, log)
    pending = {}

    def submit(ch):
        mi = ch[0][1]
        data = None
        if ship_meshes and not sp.meshes[mi][1].startswith("builtin:"):
            data = pathlib.Path(sp.meshes[mi][1]).read_bytes()
        try:
            f = ex.submit(ch, {mi: dig[mi]}, data)
        except BrokenProcessPool as e:  # the pool broke between two submissions: one new pool
            ex.broken(e, ex.gen)
            f = ex.submit(ch, {mi: dig[mi]}, data)
        pending[f] = (ch, ex.gen)

    try:
        for ch in chunks:
            submit(ch)
        while pending:
            for f in ex.wait(list(pending)):
                ch, gen = pending.pop(f)
                exc = CancelledError("cancelled with a broken pool") if f.cancelled() else f.exception()
                if exc is not None:
                    ex.broken(exc, gen)
                    rows = [{"key": k, "mesh": sp.meshes[mi][0], "mesh_digest": dig[mi], "method": sp.methods[vi].label,
                             "method_name": sp.methods[vi].name, "attack": sp.attacks[ai].label, "seed": sp.seeds[si],
                             "attempt": a, "status": "error", "error": f"worker failed: {type(exc).__name__}: {exc}"}
                            for k, mi, vi, si, ai, a in ch]
                else:
                    rows = f.result()
                writer.write(rows)
                again = [t for t, r in zip(ch, rows) if r["status"] == "error" and t[5] <= retries]
                final_fail = [r for t, r in zip(ch, rows) if r["status"] == "error" and t[5] > retries]
                for r in rows:
                    S.ok += r["status"] == "ok"
                    S.mesh_error += r["status"] == "mesh_error"
                S.failed += len(final_fail)
                S.failures += [{"key": r["key"], "mesh": r["mesh"], "method": r["method"], "attack": r["attack"],
                                "seed": r["seed"], "error": (r["error"] or "").splitlines()[0]} for r in final_fail]
                if again:
                    S.retried += len(again)
                    submit([t[:5] + (t[5] + 1,) for t in again])
                bar.update(len(rows) - len(again), failed=len(final_fail))
    finally:
        bar.close()
        ex.close()
    S.ran = S.ok + S.mesh_error + S.failed
    S.wall = time.perf_counter() - t0
    for fl in S.failures[:20]:
        log(f"[study] FAILED {fl['key'][:12]} {fl['mesh']} | {fl['method']} | {fl['attack']} | seed {fl['seed']}: {fl['error']}")
    log(f"[study] done in {S.wall:.1f} s: {S.ok} ok, {S.mesh_error} mesh errors (a result: the mesh cannot take "
        f"the method or attack), {S.failed} failed after {retries} retry, {S.retried} retried")
    with open(out / "runs.jsonl", "a") as fh:
        fh.write(json.dumps({"time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "dask": dask,
                             "workers": workers, **{k: v for k, v in S.to_dict().items() if k != "failures"},
                             "n_failures": len(S.failures)}) + "\n")
    return S


def status(out: PathLike, spec: Spec | PathLike | dict[str, Any] | None = None) -> dict:
    """Counts by status (and by method) of the results under ``out``; with ``spec`` also how many
    planned tasks are not done yet."""
    t = load_results(out)
    st = t.column("status").to_pylist()
    meth = t.column("method").to_pylist()
    d = {"rows": len(st), "by_status": {s: st.count(s) for s in sorted(set(st))}, "by_method": {}}
    for m, s in zip(meth, st):
        d["by_method"].setdefault(m, {}).setdefault(s, 0)
        d["by_method"][m][s] += 1
    if spec is not None:
        sp = spec if isinstance(spec, Spec) else load_spec(spec)
        keys, _, _ = plan(sp)
        have = set(k for k, s in zip(t.column("key").to_pylist(), st) if s in DONE)
        d["planned"] = len(keys)
        d["remaining"] = sum(k not in have for k in keys)
    errs = [(k, e) for k, s, e in zip(t.column("key").to_pylist(), st, t.column("error").to_pylist()) if s == "error"]
    d["errors"] = [{"key": k, "error": (e or "").splitlines()[0]} for k, e in errs[:50]]
    return d
