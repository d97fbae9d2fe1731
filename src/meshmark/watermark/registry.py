"""The registry of issued copies: one SQLite file that knows it is a meshmark registry.

Schema version 2 (docs/coding.md §3)::

    PRAGMA application_id = 0x4D4D5452 ('MMTR'); PRAGMA user_version = 2
    meta(name TEXT PRIMARY KEY, value TEXT NOT NULL)   -- format = 'meshmark-registry', schema_version = '2'
    assets(asset_id INTEGER PRIMARY KEY, source_sha256 TEXT UNIQUE NOT NULL, source_name TEXT,
           setup TEXT NOT NULL, n_carriers INTEGER NOT NULL, created TEXT,
           original_path TEXT, original_resolved TEXT, row_check TEXT NOT NULL)
    copies(asset_id INTEGER NOT NULL REFERENCES assets(asset_id), copy_id TEXT NOT NULL,
           codeword BLOB NOT NULL, path TEXT, created TEXT, row_check TEXT NOT NULL,
           PRIMARY KEY(asset_id, copy_id))                 -- copy ids are per asset

``row_check`` is a BLAKE2b-128 digest of the row's other fields: a changed byte inside a row is
reported as damage, not read as a different codeword or setup.

Opening (:class:`Registry`) checks, before anything is used: the file is an SQLite database with
meshmark's application id (or a version-1 registry: application id 0 and meshmark's ``meta``), its
size matches its header's page count, ``PRAGMA quick_check`` passes, the tables have meshmark's
columns, and every row's fields (types, JSON, codeword lengths, padding bits, row checks, the stored
key against its hash) are valid. A file that is not a registry gives "not a meshmark registry", a
registry that fails a check "damaged registry (integrity check failed: ...)": both MeshError. Reading
(``readonly``) uses an SQLite ``mode=ro`` connection and never writes to the file. Writing happens in
one ``BEGIN IMMEDIATE`` transaction (:meth:`Registry.begin`, which waits for another writer) and a
version-1 registry is migrated to version 2 inside that transaction.
"""
from __future__ import annotations

import datetime
import hmac
import json
import os
import secrets
import sqlite3
import time
import urllib.parse

import numpy as np

from .._core import MeshError
from .registry_checks import (HEX64, MAX_ID_CHARS, Damaged, asset_check, check_copy_id, copy_check,  # noqa: F401
                              key_hash, need, shown, text_or_null, validate_setup)

APP_ID = 0x4D4D5452  # 'MMTR'
SCHEMA_VERSION = 2
FORMAT = "meshmark-registry"
MAX_COPIES = 100_000  # per issue
MAX_CARRIERS = 1 << 24
BUSY_TIMEOUT = 5.0  # seconds SQLite itself waits for a lock, per attempt
WAIT = 600.0        # seconds issue waits for another writer before giving up

_V2 = (
    "CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT NOT NULL)",
    "CREATE TABLE assets(asset_id INTEGER PRIMARY KEY, source_sha256 TEXT UNIQUE NOT NULL, source_name TEXT, "
    "setup TEXT NOT NULL, n_carriers INTEGER NOT NULL, created TEXT, original_path TEXT, original_resolved TEXT, "
    "row_check TEXT NOT NULL)",
    "CREATE TABLE copies(asset_id INTEGER NOT NULL REFERENCES assets(asset_id), copy_id TEXT NOT NULL, "
    "codeword BLOB NOT NULL, path TEXT, created TEXT, row_check TEXT NOT NULL, PRIMARY KEY(asset_id, copy_id))",
)
_ASSET_COLS = ("asset_id", "source_sha256", "source_name", "setup", "n_carriers", "created", "original_path",
               "original_resolved", "row_check")
_COPY_COLS = ("asset_id", "copy_id", "codeword", "path", "created", "row_check")
_V1_ASSET_COLS = {"asset_id", "source_sha256", "source_name", "setup", "n_carriers", "created"}
_V1_COPY_COLS = ("copy_id", "asset_id", "codeword", "path", "created")


def now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


class Registry:
    """The SQLite registry of issued copies (module doc). ``create``: make the file if it is missing
    (a new, empty registry, mode 0600); ``readonly`` (default: ``not create``): open it with an SQLite
    read-only connection that never writes. The registry's content is read and checked when it is
    opened (and again by :meth:`begin`)."""

    def __init__(self, path, create: bool = True, readonly: bool | None = None):
        self.path = os.fspath(path)
        self.readonly = (not create) if readonly is None else bool(readonly)
        self.version = SCHEMA_VERSION
        self._in_txn = False
        if os.path.isdir(self.path):
            raise MeshError(f"'{shown(self.path)}' is a folder, not a meshmark registry")
        if not os.path.lexists(self.path):
            if not create:
                raise MeshError(f"registry '{shown(self.path)}' does not exist")
            _create(self.path)
        self._sniff()
        self.db = self._connect(readonly=True)
        try:
            self._read_txn()
            if not self.readonly:
                self.db.close()
                self.db = self._connect(readonly=False)
        except BaseException:
            self.db.close()
            raise

    # --- opening and checking -----------------------------------------------------------------
    def _not_registry(self, why: str):
        return MeshError(f"'{shown(self.path)}' is not a meshmark registry ({why})")

    def _damaged(self, why: str):
        return MeshError(f"damaged registry '{shown(self.path)}' (integrity check failed: {why})")

    def _sniff(self) -> None:
        """Header checks without SQLite, before a connection exists (once a connection holds a lock,
        this process must not open and close the file: POSIX drops every lock of a file on close)."""
        if not os.path.isfile(self.path):
            raise self._not_registry("not a regular file")
        try:
            with open(self.path, "rb") as f:
                head = f.read(100)
            size = os.path.getsize(self.path)
        except OSError as exc:
            raise MeshError(f"cannot read registry '{shown(self.path)}': {exc.strerror or exc}") from None
        if size == 0:
            raise self._not_registry("an empty file")
        if len(head) < 100 or not head.startswith(b"SQLite format 3\0"):
            raise self._not_registry("not an SQLite database")
        app = int.from_bytes(head[68:72], "big")
        if app not in (0, APP_ID):
            raise self._not_registry(f"an SQLite database of another application, application id 0x{app:08x}")
        if head[18] != 1 or head[19] != 1:
            raise self._not_registry("an SQLite database in WAL mode") if app == 0 else \
                self._damaged("the header's journal mode is not meshmark's")
        self._app = app

    def _connect(self, readonly: bool):
        try:
            if readonly:
                uri = "file:" + urllib.parse.quote(os.path.abspath(self.path)) + "?mode=ro"
                db = sqlite3.connect(uri, uri=True, timeout=BUSY_TIMEOUT, isolation_level=None)
            else:
                db = sqlite3.connect(self.path, timeout=BUSY_TIMEOUT, isolation_level=None)
        except sqlite3.Error as exc:
            raise MeshError(f"cannot open registry '{shown(self.path)}': {exc}") from None
        return db

    def _sql_error(self, exc):
        msg = str(exc)
        if os.path.exists(self.path + "-journal") and self.readonly and "readonly" in msg.replace("-", ""):
            return MeshError(f"registry '{shown(self.path)}' has an unfinished write (its -journal file): the next "
                             "`meshmark issue` into it rolls the write back")
        if "locked" in msg or "busy" in msg:
            return MeshError(f"registry '{shown(self.path)}' is busy (another process is writing it): {msg}")
        if self._app == APP_ID:
            return self._damaged(msg)
        return self._not_registry(msg)

    def _read_txn(self) -> None:
        """Read and check everything in one read transaction."""
        deadline = time.monotonic() + WAIT
        while True:
            try:
                self.db.execute("BEGIN")
                try:
                    self._load()
                finally:
                    self.db.execute("COMMIT") if self.db.in_transaction else None
                return
            except sqlite3.OperationalError as exc:
                if ("locked" in str(exc) or "busy" in str(exc)) and time.monotonic() < deadline:
                    time.sleep(0.05)
                    continue
                raise self._sql_error(exc) from None
            except sqlite3.Error as exc:
                raise self._sql_error(exc) from None

    def _load(self) -> None:
        db = self.db
        db.execute("SELECT COUNT(*) FROM sqlite_master").fetchone()  # takes the shared lock
        page = db.execute("PRAGMA page_size").fetchone()[0]
        n_pages = db.execute("PRAGMA page_count").fetchone()[0]  # the header's count, when valid
        size = os.stat(self.path).st_size
        if size != page * n_pages:
            raise self._damaged(f"the file has {size} bytes, its header says {n_pages} pages of {page}")
        app = db.execute("PRAGMA application_id").fetchone()[0]
        uv = db.execute("PRAGMA user_version").fetchone()[0]
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        if app == 0:
            if not {"meta", "assets", "copies"} <= tables:
                raise self._not_registry("it has no meshmark tables")
            rows = dict(db.execute("SELECT name, value FROM meta").fetchall())
            if rows.get("schema_version") != "1" or uv != 0:
                raise self._not_registry(f"no meshmark schema version (meta: {str(rows)[:80]})")
            self.version = 1
        elif uv != SCHEMA_VERSION:
            raise MeshError(f"registry '{shown(self.path)}' has schema version {uv}; this meshmark reads versions 1 "
                            f"and {SCHEMA_VERSION}" + (" (written by a newer meshmark)" if uv > SCHEMA_VERSION else ""))
        else:
            self.version = SCHEMA_VERSION
        check = db.execute("PRAGMA quick_check").fetchall()
        if check != [("ok",)]:
            raise self._damaged("; ".join(str(r[0]) for r in check[:3]))
        try:
            self._load_rows(tables)
        except Damaged as exc:
            raise self._damaged(str(exc)) from None

    def _load_rows(self, tables) -> None:
        db = self.db
        cols = lambda t: tuple(r[1] for r in db.execute(f"PRAGMA table_info({t})"))
        acols, ccols = cols("assets"), cols("copies")
        if self.version == 1:
            need(_V1_ASSET_COLS <= set(acols) <= _V1_ASSET_COLS | {"original_path", "original_resolved"},
                  f"assets columns {acols}")
            need(set(ccols) == set(_V1_COPY_COLS), f"copies columns {ccols}")
        else:
            need(tables == {"meta", "assets", "copies"}, f"tables {sorted(tables)}")
            need(acols == _ASSET_COLS and ccols == _COPY_COLS, "the tables' columns are not meshmark's")
            meta = db.execute("SELECT name, value FROM meta ORDER BY name").fetchall()
            need(meta == [("format", FORMAT), ("schema_version", str(SCHEMA_VERSION))], f"meta {meta!r}"[:120])
        has_orig = "original_path" in acols
        sel = ", ".join(c if c in acols else "NULL" for c in _ASSET_COLS)
        self._assets, self._asset_rows, self._by_sha = {}, {}, {}
        for row in db.execute(f"SELECT {sel} FROM assets ORDER BY asset_id"):
            aid, sha, name, setup, C, created, op, orr, chk = row
            need(isinstance(aid, int), "assets.asset_id")
            need(isinstance(sha, str) and HEX64.fullmatch(sha), f"asset {aid}: source_sha256")
            need(isinstance(C, int) and not isinstance(C, bool) and 1 <= C <= MAX_CARRIERS, f"asset {aid}: n_carriers")
            for v, what in ((name, "source_name"), (created, "created"), (op, "original_path"),
                            (orr, "original_resolved")):
                text_or_null(v, f"asset {aid}: {what}")
            if self.version >= 2:
                need(isinstance(chk, str) and hmac.compare_digest(chk, asset_check(row[:-1])),
                      f"asset {aid}: the row check does not match its fields")
            s = validate_setup(setup, C, aid)
            self._assets[aid] = (s, C)
            self._asset_rows[aid] = list(row[:-1])
            self._by_sha[sha] = aid
        del has_orig
        self._copies = {aid: ([], []) for aid in self._assets}
        sel = ", ".join(_COPY_COLS if self.version >= 2 else _V1_COPY_COLS[1::-1] + _V1_COPY_COLS[2:] + ("NULL",))
        for row in db.execute(f"SELECT {sel} FROM copies ORDER BY rowid"):
            aid, cid, cw, path, created, chk = row
            need(aid in self._assets, f"copy {str(cid)[:40]!r}: asset {aid!r} does not exist")
            need(isinstance(cid, str) and cid.strip() and len(cid) <= 1000, f"asset {aid}: a copy id")
            C = self._assets[aid][1]
            need(isinstance(cw, bytes) and len(cw) == (C + 7) // 8,
                  f"asset {aid}, copy {cid[:40]!r}: the codeword has {len(cw) if isinstance(cw, bytes) else 'no'} "
                  f"bytes, {C} carriers need {(C + 7) // 8}")
            need(C % 8 == 0 or cw[-1] & ((1 << (8 - C % 8)) - 1) == 0,
                  f"asset {aid}, copy {cid[:40]!r}: the codeword's padding bits are set")
            text_or_null(path, f"asset {aid}, copy {cid[:40]!r}: path")
            text_or_null(created, f"asset {aid}, copy {cid[:40]!r}: created")
            if self.version >= 2:
                need(isinstance(chk, str) and hmac.compare_digest(chk, copy_check(row[:-1])),
                      f"asset {aid}, copy {cid[:40]!r}: the row check does not match its fields")
            ids, words = self._copies[aid]
            ids.append(cid)
            words.append(cw)
        if self.version == 1:
            seen = [c for ids, _ in self._copies.values() for c in ids]
            need(len(seen) == len(set(seen)), "a copy id is listed twice")
        for ids, _ in self._copies.values():
            need(len(ids) == len(set(ids)), "a copy id is listed twice for one asset")

    # --- reading ------------------------------------------------------------------------------
    def close(self):
        if self._in_txn:
            self.rollback()
        self.db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def asset(self, sha: str):
        aid = self._by_sha.get(sha)
        return None if aid is None else (aid, self._assets[aid][0])

    def assets(self):
        """[(asset_id, setup, n_carriers)] of every asset."""
        return [(aid, s, C) for aid, (s, C) in self._assets.items()]

    def source_name(self, asset_id: int):
        return self._asset_rows[asset_id][2]

    def original(self, asset_id: int):
        """(path as given, resolved path, source_sha256) of an asset; paths None when not recorded."""
        row = self._asset_rows.get(asset_id)
        return (None, None, None) if row is None else (row[6], row[7], row[1])

    def copy_ids(self, asset_id: int) -> set:
        return set(self._copies.get(asset_id, ([], []))[0])

    def n_copies(self, asset_id: int | None = None) -> int:
        if asset_id is not None:
            return len(self._copies.get(asset_id, ([], []))[0])
        return sum(len(ids) for ids, _ in self._copies.values())

    def codewords(self, asset_id: int, n: int):
        """(copy ids, (N, n) uint8 codewords) of an asset."""
        ids, words = self._copies.get(asset_id, ([], []))
        if not ids:
            return [], np.zeros((0, n), np.uint8)
        packed = np.frombuffer(b"".join(words), np.uint8).reshape(len(ids), (n + 7) // 8)
        return list(ids), np.unpackbits(packed, axis=1)[:, :n]

    # --- writing (inside begin() ... commit()) -------------------------------------------------
    def begin(self, wait: float = WAIT) -> None:
        """Take the write lock (``BEGIN IMMEDIATE``; waits up to ``wait`` seconds for another writer),
        re-read and check the registry under it, and migrate a version-1 registry."""
        if self.readonly:
            raise MeshError(f"registry '{shown(self.path)}' was opened read-only")
        deadline = time.monotonic() + wait
        self.db.execute(f"PRAGMA busy_timeout = {int(1000 * min(wait, BUSY_TIMEOUT))}")  # a short wait stays short
        while True:
            try:
                self.db.execute("BEGIN IMMEDIATE")
                break
            except sqlite3.OperationalError as exc:
                if ("locked" in str(exc) or "busy" in str(exc)) and time.monotonic() < deadline:
                    time.sleep(0.05 + 0.1 * secrets.randbelow(10) / 10)
                    continue
                raise self._sql_error(exc) from None
        self._in_txn = True
        try:
            self._load()
            if self.version == 1:
                self._migrate()
        except sqlite3.Error as exc:
            self.rollback()
            raise self._sql_error(exc) from None
        except BaseException:
            self.rollback()
            raise

    def _migrate(self) -> None:
        """Version 1 -> 2 in the open transaction: application id, user_version, meta, row checks,
        per-asset copy ids (v1 ids were unique in the whole registry, so they stay valid)."""
        db = self.db
        assets = {aid: list(row) for aid, row in self._asset_rows.items()}
        copies = db.execute("SELECT asset_id, copy_id, codeword, path, created FROM copies ORDER BY rowid").fetchall()
        db.execute("DROP TABLE copies")
        db.execute("DROP TABLE assets")
        db.execute("DROP TABLE meta")
        for stmt in _V2:
            db.execute(stmt)
        db.execute("INSERT INTO meta VALUES ('format', ?), ('schema_version', ?)", (FORMAT, str(SCHEMA_VERSION)))
        for row in assets.values():
            db.execute(f"INSERT INTO assets VALUES ({', '.join('?' * 9)})", (*row, asset_check(row)))
        db.executemany(f"INSERT INTO copies VALUES ({', '.join('?' * 6)})", [(*r, copy_check(r)) for r in copies])
        db.execute(f"PRAGMA application_id = {APP_ID}")
        db.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
        self.version = SCHEMA_VERSION
        try:
            os.chmod(self.path, 0o600)
        except OSError:
            pass

    def add_asset(self, sha: str, name: str, setup: dict, n: int) -> int:
        aid = max(self._assets, default=0) + 1
        row = [aid, sha, name, json.dumps(setup, allow_nan=False), int(n), now(), None, None]
        self.db.execute(f"INSERT INTO assets VALUES ({', '.join('?' * 9)})", (*row, asset_check(row)))
        self._assets[aid] = (setup, int(n))
        self._asset_rows[aid] = row
        self._by_sha[sha] = aid
        self._copies[aid] = ([], [])
        return aid

    def set_original(self, asset_id: int, path: str) -> None:
        """Record where the asset's original is (as given, and resolved)."""
        row = self._asset_rows[asset_id]
        row[6], row[7] = str(path), os.path.realpath(path)
        self.db.execute("UPDATE assets SET original_path = ?, original_resolved = ?, row_check = ? WHERE asset_id = ?",
                        (row[6], row[7], asset_check(row), asset_id))

    def add_copies(self, asset_id: int, rows) -> None:
        """``rows``: [(copy_id, packed codeword bytes, path or None)]."""
        t = now()
        full = [(asset_id, cid, blob, path, t) for cid, blob, path in rows]
        self.db.executemany(f"INSERT INTO copies VALUES ({', '.join('?' * 6)})", [(*r, copy_check(r)) for r in full])
        ids, words = self._copies[asset_id]
        ids.extend(r[1] for r in full)
        words.extend(r[2] for r in full)

    def set_paths(self, paths: dict, asset_id: int | None = None) -> None:
        """Record where copies were written (copy id -> path); without ``asset_id``, the copy of that id
        recorded last."""
        for cid, p in paths.items():
            where, args = ("asset_id = ? AND copy_id = ?", (asset_id, cid)) if asset_id is not None else \
                ("rowid = (SELECT MAX(rowid) FROM copies WHERE copy_id = ?)", (cid,))
            row = self.db.execute(f"SELECT asset_id, copy_id, codeword, path, created FROM copies WHERE {where}",
                                  args).fetchone()
            if row is None:
                raise MeshError(f"registry '{shown(self.path)}' has no copy {cid!r}")
            r = (*row[:3], str(p), row[4])
            self.db.execute("UPDATE copies SET path = ?, row_check = ? WHERE asset_id = ? AND copy_id = ?",
                            (str(p), copy_check(r), row[0], row[1]))

    def commit(self) -> None:
        try:
            self.db.execute("COMMIT")
        except sqlite3.Error as exc:
            self.rollback()
            raise self._sql_error(exc) from None
        finally:
            self._in_txn = False

    def rollback(self) -> None:
        try:
            if self.db.in_transaction:
                self.db.execute("ROLLBACK")
        except sqlite3.Error:
            pass
        self._in_txn = False
        self._read_back()

    def _read_back(self):
        try:
            if not self.db.in_transaction:
                self.db.execute("BEGIN")
                try:
                    self._load()
                finally:
                    self.db.execute("COMMIT")
        except (sqlite3.Error, MeshError):
            pass


def _create(path: str) -> None:
    """A new, empty version-2 registry at ``path`` (mode 0600), made under a temporary name and
    linked into place, so the path never holds a half-made registry; if another process made it
    first, theirs is kept."""
    from ..atomic import check_writable, temp_path

    check_writable(path, "registry")
    tmp = temp_path(path)
    try:
        os.close(os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
        db = sqlite3.connect(tmp, isolation_level=None)
        try:
            db.execute("BEGIN")
            for stmt in _V2:
                db.execute(stmt)
            db.execute("INSERT INTO meta VALUES ('format', ?), ('schema_version', ?)", (FORMAT, str(SCHEMA_VERSION)))
            db.execute(f"PRAGMA application_id = {APP_ID}")
            db.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
            db.execute("COMMIT")
        finally:
            db.close()
        try:
            os.link(tmp, path)
        except FileExistsError:
            pass
        except OSError:  # no hard links on this file system
            if not os.path.lexists(path):
                os.replace(tmp, path)
    except OSError as exc:
        raise MeshError(f"cannot create registry '{shown(path)}': {exc.strerror or exc}") from None
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
