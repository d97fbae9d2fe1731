"""Copy tracing (fingerprinting): many marked copies of one asset, and which one leaked.

:func:`issue` marks N copies of a mesh, each with its own random codeword of C bits (one per carrier,
whitened and placed with the owner's key exactly as a payload is), all with the same parameters and
the original's side information, and records them in a registry (:class:`Registry`, one SQLite file).
:func:`trace` reads the carriers of a suspect mesh and correlates the bits with every codeword issued:
the best copy j has m_j matching bits out of C; for an unmarked mesh (or another asset) each
codeword matches like a fair coin, so the false-alarm probability, corrected for the N codewords
compared (Bonferroni), is::

    p_false_alarm = min(1, N * P(Bin(C, 1/2) >= m_best))

and a copy is named only when ``p_false_alarm < 1e-6`` (else ``copy`` is None: "none"). The same bound
holds for naming a *wrong* copy when the suspect is copy i (the other codewords are independent of
copy i's). With C carriers read perfectly, ``N 2^-C < 1e-6`` needs C >= 27 for N = 100 (26 carriers
rank the right copy first among 100 but certify only 100 * 2^-26 = 1.5e-6).

Registry schema (``schema_version`` 1)::

    meta(name TEXT PRIMARY KEY, value TEXT)            -- 'schema_version' = '1'
    assets(asset_id INTEGER PRIMARY KEY,               -- one row per marked original
           source_sha256 TEXT UNIQUE NOT NULL,         -- of the welded V (float64) and faces
           source_name TEXT, setup TEXT NOT NULL,      -- JSON: method, params, choice, weld, key
                                                       -- (or null), side_info (carriers), mesh
           n_carriers INTEGER NOT NULL, created TEXT,
           original_path TEXT,                         -- the original as given to issue (nullable)
           original_resolved TEXT)                     -- its absolute, symlink-resolved path (nullable)
    copies(copy_id TEXT PRIMARY KEY, asset_id INTEGER NOT NULL REFERENCES assets(asset_id),
           codeword BLOB NOT NULL,                     -- C bits, numpy.packbits order
           path TEXT, created TEXT)

A second :func:`issue` of the same original into the same registry adds copies to its asset with
the asset's parameters and side information.

Informed tracing (:mod:`.informed`, docs/tracing.md): every copy also carries a keyed low-pass
pattern (settings in ``setup['informed']``; the field of copy j is derived from the key, the digest
and the copy id, nothing per copy is stored). When the original is available to :func:`trace`
(given, or found at the recorded path with the recorded digest) the pattern is correlated too and
the two tests are combined by Bonferroni: ``p = min(1, 2 min(p_blind, p_informed))``.
"""
from __future__ import annotations

import datetime
import hashlib
import json
import os
import secrets
import sqlite3

import numpy as np

from .._core import MeshError
from ..mesh import as_mesh
from ..metrics import false_alarm_probability
from . import informed as _informed
from . import keys as _keys
from .framework import DETECTION_THRESHOLD, MAX_ROUNDS, MIN_CARRIERS, _weld, embed_channel
from .informed import source_digest  # noqa: F401  (tracing.source_digest: part of this module's API)
from .keyfile import Keyfile
from .methods import method_named

SCHEMA_VERSION = "1"
# params="auto" for copies: the first rung of the ladder with at least 64 carriers (27 certify one
# copy among 100 only when every bit reads right; 64 still certify it with 10 of the 64 bits wrong
# among 100 copies, 7 among 10,000)
TRACE_CARRIERS = 64

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta(name TEXT PRIMARY KEY, value TEXT);
CREATE TABLE IF NOT EXISTS assets(asset_id INTEGER PRIMARY KEY, source_sha256 TEXT UNIQUE NOT NULL, source_name TEXT,
    setup TEXT NOT NULL, n_carriers INTEGER NOT NULL, created TEXT);
CREATE TABLE IF NOT EXISTS copies(copy_id TEXT PRIMARY KEY, asset_id INTEGER NOT NULL REFERENCES assets(asset_id),
    codeword BLOB NOT NULL, path TEXT, created TEXT);
CREATE INDEX IF NOT EXISTS copies_asset ON copies(asset_id);
"""
_ASSET_COLUMNS = (("original_path", "TEXT"), ("original_resolved", "TEXT"))  # added by informed tracing


def _now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


class Registry:
    """The SQLite registry of issued copies (see the module doc for the schema)."""

    def __init__(self, path, create: bool = True):
        self.path = os.fspath(path)
        if not create and not os.path.isfile(self.path):
            raise MeshError(f"registry '{self.path}' does not exist")
        try:
            self.db = sqlite3.connect(self.path)
            self.db.executescript(_SCHEMA)
            row = self.db.execute("SELECT value FROM meta WHERE name = 'schema_version'").fetchone()
            if row is None:
                self.db.execute("INSERT INTO meta VALUES ('schema_version', ?)", (SCHEMA_VERSION,))
                self.db.commit()
            elif row[0] != SCHEMA_VERSION:
                raise MeshError(f"registry '{self.path}' has schema version {row[0]}, this meshmark reads {SCHEMA_VERSION}")
            self._columns = {r[1] for r in self.db.execute("PRAGMA table_info(assets)")}
        except sqlite3.DatabaseError as exc:
            raise MeshError(f"'{self.path}' is not a meshmark registry ({exc})") from None

    def close(self):
        self.db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def asset(self, sha: str):
        row = self.db.execute("SELECT asset_id, setup FROM assets WHERE source_sha256 = ?", (sha,)).fetchone()
        return None if row is None else (row[0], json.loads(row[1]))

    def add_asset(self, sha: str, name: str, setup: dict, n: int) -> int:
        cur = self.db.execute("INSERT INTO assets(source_sha256, source_name, setup, n_carriers, created) "
                              "VALUES (?, ?, ?, ?, ?)", (sha, name, json.dumps(setup), n, _now()))
        return int(cur.lastrowid)

    def _add_columns(self):
        for name, kind in _ASSET_COLUMNS:  # additive: registries written before informed tracing
            if name not in self._columns:
                self.db.execute(f"ALTER TABLE assets ADD COLUMN {name} {kind}")
                self._columns.add(name)

    def set_original(self, asset_id: int, path: str) -> None:
        """Record where the asset's original is (as given, and resolved)."""
        self._add_columns()
        self.db.execute("UPDATE assets SET original_path = ?, original_resolved = ? WHERE asset_id = ?",
                        (str(path), os.path.realpath(path), asset_id))

    def original(self, asset_id: int):
        """(path as given, resolved path, source_sha256) of an asset; paths None when not recorded."""
        cols = "original_path, original_resolved" if "original_path" in self._columns else "NULL, NULL"
        row = self.db.execute(f"SELECT {cols}, source_sha256 FROM assets WHERE asset_id = ?", (asset_id,)).fetchone()
        return (None, None, None) if row is None else tuple(row)

    def copy_ids(self) -> set:
        return {r[0] for r in self.db.execute("SELECT copy_id FROM copies")}

    def n_copies(self) -> int:
        return int(self.db.execute("SELECT COUNT(*) FROM copies").fetchone()[0])

    def assets(self):
        return [(r[0], json.loads(r[1]), r[2]) for r in self.db.execute("SELECT asset_id, setup, n_carriers FROM assets")]

    def codewords(self, asset_id: int, n: int):
        """(copy ids, (N, n) uint8 codewords) of an asset."""
        rows = self.db.execute("SELECT copy_id, codeword FROM copies WHERE asset_id = ? ORDER BY rowid",
                               (asset_id,)).fetchall()
        if not rows:
            return [], np.zeros((0, n), np.uint8)
        nb = (n + 7) // 8
        packed = np.frombuffer(b"".join(r[1] for r in rows), np.uint8).reshape(len(rows), nb)
        return [r[0] for r in rows], np.unpackbits(packed, axis=1)[:, :n]


def _setup_keyfile(setup: dict, key: str) -> Keyfile:
    """A Keyfile-shaped view of an asset's setup (for the framework's carrier reading)."""
    return Keyfile(method=setup["method"], params=setup["params"], key=key, payload={}, weld=setup["weld"],
                   coding={"scheme": "trace", "n_coded": len(setup["side_info"]["carriers"])},
                   side_info=setup["side_info"], mesh=setup["mesh"], choice=setup.get("choice"))


def issue(V, F=None, *, key, registry, n_copies: int = None, ids=None, method: str = "laplacian", params="auto",
          weld: bool = True, store_key: bool = True, source_name: str = "", progress=None, original=None,
          informed: bool = True, **method_params):
    """Mark copies of the mesh, each with its own random codeword; record them in ``registry`` (a
    path or :class:`Registry`). Give ``n_copies`` (ids continue the registry's numbering: ``0001``, ...)
    or ``ids`` (strings, unique in the registry). Returns a list of ``(copy_id, V)`` with V the
    marked vertices (input order). Nothing is recorded unless every copy is marked.

    ``informed`` (default on, for a new asset): each copy also carries its keyed low-pass pattern
    (:mod:`.informed`); ``original``: the path of the original file, recorded so that :func:`trace`
    can find it (optional; ``meshmark issue`` records IN)."""
    report = progress or (lambda f, t: None)
    mesh_in = as_mesh(V, F)
    key = _keys.check_key(key)
    m = method_named(method)
    reg = registry if isinstance(registry, Registry) else Registry(registry)
    try:
        existing = reg.copy_ids()
        if (n_copies is None) == (ids is None):
            raise MeshError("give either the number of copies or their ids")
        if ids is None:
            if not isinstance(n_copies, (int, np.integer)) or n_copies < 1:
                raise MeshError(f"the number of copies must be a positive integer, got {n_copies!r}")
            start = reg.n_copies() + 1
            ids = []
            i = start
            while len(ids) < n_copies:
                cid = f"{i:04d}"
                if cid not in existing:
                    ids.append(cid)
                i += 1
        ids = [str(c).strip() for c in ids]
        if not ids or any(not c for c in ids):
            raise MeshError("copy ids must be non-empty")
        dup = sorted({c for c in ids if ids.count(c) > 1} | (set(ids) & existing))
        if dup:
            raise MeshError(f"copy id(s) already used: {', '.join(dup[:5])}")
        w = _weld(mesh_in, weld)
        mesh = w.mesh if w is not None else mesh_in
        sha = source_digest(mesh)
        found = reg.asset(sha)
        if found is None:
            from .auto import choose
            p, cids, side, choice = choose(mesh, m, params, method_params, None, need=TRACE_CARRIERS)
            side = dict(side)
            asset_id = None
            inf_params = _informed.default_params(mesh) if informed else None
        else:
            asset_id, setup = found
            if setup["method"] != method:
                raise MeshError(f"the registry holds this mesh with the {setup['method']} method, not {method}")
            if setup.get("key_sha256") != hashlib.sha256(key.encode()).hexdigest():
                raise MeshError("the registry holds this mesh under another key")
            p, choice = setup["params"], setup.get("choice")
            inf_params = setup.get("informed")
            cids = np.asarray(setup["side_info"]["carriers"], np.int64)
            side = {k: v for k, v in setup["side_info"].items() if k != "carriers"}
        C = int(len(cids))
        if C < MIN_CARRIERS:
            raise MeshError(f"the mesh offers only {C} carrier bits to the {method} method; at least {MIN_CARRIERS} are needed")
        white = _keys.whitening(key, method, C)
        order = _keys.permutation(key, method, C)
        carriers = np.asarray(cids)[order]
        out, rows = [], []
        trace_side = side if found is not None else None
        orig = _informed.Original(mesh, inf_params) if inf_params else None
        pats = None
        for j, cid in enumerate(ids):
            report(j / len(ids), f"copy {cid}")
            cw = np.unpackbits(np.frombuffer(secrets.token_bytes((C + 7) // 8), np.uint8))[:C]
            base = mesh
            if orig is not None:  # the keyed pattern first; the blind mark on top is checked below
                if j % _informed._BATCH == 0:
                    pats = orig.patterns([_informed.copy_seed(key, sha, c) for c in ids[j:j + _informed._BATCH]])
                base = mesh.with_vertices(orig.marked(pats[:, j % _informed._BATCH]))
            Vm, s_j, _ = embed_channel(base, m, p, dict(trace_side or side), carriers, cw ^ white)
            if trace_side is None:
                trace_side = s_j  # the first copy's side information serves every copy
            # every copy must read back with the one side information kept for the asset: re-embed the
            # carriers that do not (the marked mesh's scale differs slightly from copy to copy)
            ch = cw ^ white
            for _ in range(MAX_ROUNDS):
                got, _ = m.extract(mesh.with_vertices(Vm), p, trace_side, carriers)
                bad = np.flatnonzero(got != ch)
                if bad.size == 0:
                    break
                Vm, _, _ = m.embed(mesh.with_vertices(Vm), p, dict(trace_side), carriers[bad], ch[bad])
            else:
                got, _ = m.extract(mesh.with_vertices(Vm), p, trace_side, carriers)
                bad = np.flatnonzero(got != ch)
            if bad.size:
                raise MeshError(f"copy {cid}: {bad.size} of {C} carrier bits do not read back with the shared side "
                                "information; nothing was recorded")
            out.append((cid, w.scatter(Vm) if w is not None else Vm))
            rows.append((cid, np.packbits(cw).tobytes()))
        if asset_id is None:
            setup = {"method": method, "params": p, "choice": choice, "weld": bool(weld),
                     "key": key if store_key else None, "key_sha256": hashlib.sha256(key.encode()).hexdigest(),
                     "side_info": {**trace_side, "carriers": [int(c) for c in cids]},
                     "mesh": {"n_vertices": mesh.n_vertices, "n_faces": mesh.n_faces}}
            if inf_params:
                setup["informed"] = inf_params
            asset_id = reg.add_asset(sha, source_name, setup, C)
        if original is not None:
            reg.set_original(asset_id, os.fspath(original))
        now = _now()
        reg.db.executemany("INSERT INTO copies(copy_id, asset_id, codeword, path, created) VALUES (?, ?, ?, NULL, ?)",
                           [(cid, asset_id, blob, now) for cid, blob in rows])
        reg.db.commit()
        report(1.0, "done")
        return out
    except BaseException:
        reg.db.rollback()
        raise
    finally:
        if not isinstance(registry, Registry):
            reg.close()


def set_paths(registry, paths: dict) -> None:
    """Record where copies were written (copy id -> path)."""
    reg = registry if isinstance(registry, Registry) else Registry(registry, create=False)
    try:
        reg.db.executemany("UPDATE copies SET path = ? WHERE copy_id = ?", [(p, c) for c, p in paths.items()])
        reg.db.commit()
    finally:
        if not isinstance(registry, Registry):
            reg.close()


def trace(V, F=None, *, registry, key=None, original=None) -> dict:
    """Which issued copy is this mesh? Returns a dict with ``detected``, ``copy`` (id or None),
    ``p_false_alarm`` (corrected for every codeword compared and, when the original was used, for the
    two tests), ``evidence`` (``"informed+blind"`` or ``"blind"``), ``matches``, ``n_carriers``,
    ``n_copies``, ``asset_id``, ``second_matches``, ``blind`` and ``informed`` (each test's best copy,
    its p and details; ``informed`` is None without an original) and ``originals`` (per asset: where
    the original was looked for and whether it was used).

    ``original``: the original (a path or a Mesh); without it the path recorded by :func:`issue` is
    tried, and an original whose digest differs from the registry's is not used (blind only). A given
    original that matches no asset of the registry is a MeshError."""
    from ..io import read_mesh

    mesh0 = as_mesh(V, F)
    given = None
    if original is not None:
        given = read_mesh(os.fspath(original)) if isinstance(original, (str, os.PathLike)) else as_mesh(original)
    reg = registry if isinstance(registry, Registry) else Registry(registry, create=False)
    try:
        assets = reg.assets()
        n_total = reg.n_copies()
        best, best_inf, originals = None, None, []
        for asset_id, setup, C in assets:
            k = key if key is not None else setup.get("key")
            if k is None:
                raise MeshError("the registry does not store the key: give --key")
            k = _keys.check_key(k)
            from .framework import _prepare, read_soft
            kf = _setup_keyfile(setup, k)
            mesh, _, _, _ = _prepare(mesh0, kf)
            bits, soft = read_soft(mesh, kf, k)
            cids, W = reg.codewords(asset_id, C)
            if not cids:
                continue
            b = bits.astype(np.int32)
            Wi = W.astype(np.int32)
            matches = C - int(b.sum()) - Wi.sum(1) + 2 * (Wi @ b)
            score = (2.0 * W - 1.0) @ soft  # soft correlation breaks ties
            j = int(np.lexsort((-score, -matches))[0])
            second = int(np.partition(matches, -2)[-2]) if len(cids) > 1 else 0
            cand = {"asset_id": asset_id, "copy_id": cids[j], "matches": int(matches[j]), "n_carriers": int(C),
                    "second_matches": second}
            if best is None or false_alarm_probability(cand["matches"], C) < false_alarm_probability(best["matches"], best["n_carriers"]):
                best = cand
            orig, info = _informed.find_original(reg, asset_id, setup, given)
            originals.append(info)
            if orig is not None:
                sha = reg.original(asset_id)[2]
                det = _informed.detect(_informed._welded(mesh0, bool(setup["weld"])), orig,
                                       [_informed.copy_seed(k, sha, c) for c in cids])
                z = det.pop("z")
                jz = int(np.argmax(z))
                zs = np.sort(z)
                inf = {"asset_id": asset_id, "copy_id": cids[jz], "z": float(z[jz]),
                       "second_z": float(zs[-2]) if len(zs) > 1 else 0.0, **det}
                if best_inf is None or inf["z"] > best_inf["z"]:
                    best_inf = inf
        if given is not None and not any(o["status"] == "given" for o in originals):
            raise MeshError("the original given is not the original of any asset in the registry (its digest differs)")
        if best is None:
            return {"detected": False, "copy": None, "p_false_alarm": 1.0, "evidence": "blind", "matches": 0,
                    "n_carriers": 0, "n_copies": n_total, "asset_id": None, "second_matches": 0,
                    "blind": None, "informed": None, "originals": originals}
        p_blind = min(1.0, n_total * false_alarm_probability(best["matches"], best["n_carriers"]))
        blind = {"copy": best["copy_id"], "asset_id": best["asset_id"], "p_false_alarm": p_blind,
                 "matches": best["matches"], "n_carriers": best["n_carriers"]}
        informed = None
        winner, p = blind, p_blind
        if best_inf is not None:
            p_inf = min(1.0, n_total * _informed.tail_probability(best_inf["z"]))
            informed = {"copy": best_inf.pop("copy_id"), "p_false_alarm": p_inf, **best_inf}
            p = min(1.0, 2.0 * min(p_blind, p_inf))  # Bonferroni over the two tests
            if p_inf < p_blind:
                winner = informed
        detected = bool(p < DETECTION_THRESHOLD)
        return {"detected": detected, "copy": winner["copy"] if detected else None, "p_false_alarm": p,
                "evidence": "informed+blind" if informed is not None else "blind",
                "matches": best["matches"], "n_carriers": best["n_carriers"], "n_copies": n_total,
                "asset_id": winner["asset_id"] if detected else None, "second_matches": best["second_matches"],
                "blind": blind, "informed": informed, "originals": originals}
    finally:
        if not isinstance(registry, Registry):
            reg.close()
