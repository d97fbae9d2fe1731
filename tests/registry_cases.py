"""Damaged and foreign registries for tests/test_registry_hardening.py (and bench/registry_concurrency.py):
each case writes one file (or folder) into a fresh directory and says whether it is foreign (must
stay byte-identical and be called "not a meshmark registry") or a damaged meshmark registry."""
from __future__ import annotations

import gzip
import json
import os
import shutil
import sqlite3
import subprocess
import sys

import numpy as np

import meshmark
from meshmark.watermark import tracing
from meshmark.watermark.registry import Registry
from meshmark.watermark.registry_checks import asset_check, copy_check


def _edit(path, sql, args=(), fix_checks=True):
    """Run ``sql`` on the registry at ``path`` (as any SQLite tool could) and, ``fix_checks``,
    recompute every row check so that only the field validation can see the change."""
    db = sqlite3.connect(path, isolation_level=None)
    db.execute("BEGIN")
    if callable(sql):
        sql(db)
    else:
        db.execute(sql, args)
    if fix_checks:
        try:
            for row in db.execute("SELECT asset_id, source_sha256, source_name, setup, n_carriers, created, "
                                  "original_path, original_resolved FROM assets").fetchall():
                db.execute("UPDATE assets SET row_check = ? WHERE rowid = ?", (asset_check(row), row[0]))
            for r in db.execute("SELECT rowid, asset_id, copy_id, codeword, path, created FROM copies").fetchall():
                db.execute("UPDATE copies SET row_check = ? WHERE rowid = ?", (copy_check(r[1:]), r[0]))
        except (sqlite3.Error, TypeError, ValueError):
            pass
    db.execute("COMMIT")
    db.close()


def _setup_cases(setup: dict):
    """(name, new setup text) with a value no valid registry holds."""
    s = json.dumps
    out = [("setup-not-json", s(setup)[:-7] + "{"), ("setup-half", s(setup)[: len(s(setup)) // 2]),
           ("setup-list", "[]"), ("setup-null", "null"), ("setup-number", "7"), ("setup-empty", ""),
           ("setup-nan", s(setup).replace('"weld": true', '"weld": NaN').replace('"weld": false', '"weld": NaN')),
           ("setup-deep", "[" * 100000 + "]" * 100000), ("setup-1e999", s({**setup, "weld": 1}).replace(": 1", ": 1e999", 1))]
    for k in ("method", "params", "weld", "key_sha256", "side_info", "mesh"):
        out.append((f"setup-drop-{k}", s({a: b for a, b in setup.items() if a != k})))
        for bad in ([], "x", 3, {}):
            if isinstance(bad, type(setup[k])) and not (isinstance(bad, dict) and k == "params"):
                continue
            out.append((f"setup-{k}-{type(bad).__name__}", s({**setup, k: bad})))
    car = setup["side_info"]["carriers"]
    for name, c in (("dup", [car[0]] + car[:-1]), ("neg", [-1] + car[1:]), ("huge", [2**40] + car[1:]),
                    ("text", ["a"] + car[1:]), ("short", car[:-1]), ("long", car + [10**6]), ("bool", [True] + car[1:]),
                    ("dict", {"0": 1})):
        out.append((f"setup-carriers-{name}", s({**setup, "side_info": {**setup["side_info"], "carriers": c}})))
    for name, p in (("K-neg", -1), ("K-text", "x"), ("K-huge", 10**12)):
        out.append((f"setup-params-{name}", s({**setup, "params": {**setup["params"], "K": p}})))
    out += [("setup-key-changed", s({**setup, "key": setup.get("key", "k") + "x"})),
            ("setup-key-number", s({**setup, "key": 5})),
            ("setup-mesh-nv-text", s({**setup, "mesh": {**setup["mesh"], "n_vertices": "x"}})),
            ("setup-mesh-nv-neg", s({**setup, "mesh": {**setup["mesh"], "n_vertices": -3}})),
            ("setup-informed-version", s({**setup, "informed": {"version": 99}})),
            ("setup-informed-list", s({**setup, "informed": [1]})),
            ("setup-informed-t-neg", s({**setup, "informed": {**setup.get("informed", {"version": 1}), "t": -1.0}})),
            ("setup-choice-list", s({**setup, "choice": [1]})),
            ("setup-method-unknown", s({**setup, "method": "nope"}))]
    return out


def _bytes_builder(data: bytes):
    """builder(dir) -> path of a file ``r.sqlite`` in dir holding ``data``."""
    def build(d):
        p = os.path.join(d, "r.sqlite")
        with open(p, "wb") as f:
            f.write(data)
        return p
    return build


def damaged_cases(good: bytes, setup: dict, n_carriers: int, seed: int = 0):
    """[(name, builder(dir) -> path)] of damaged meshmark registries made from ``good``."""
    rng = np.random.default_rng(seed)
    size = len(good)
    page = int.from_bytes(good[16:18], "big")
    cases = []

    def from_bytes(name, data):
        cases.append((name, _bytes_builder(data)))

    def from_sql(name, sql, args=(), fix_checks=True):
        def build(d):
            p = os.path.join(d, "r.sqlite")
            with open(p, "wb") as f:
                f.write(good)
            _edit(p, sql, args, fix_checks)
            return p
        cases.append((name, build))

    cuts = {1, 16, 50, 99, 100, 101, 511, page - 1, page, page + 1, 2 * page, 3 * page - 7, size - 1000, size - 1,
            size - page, size // 2, size - 2 * page}
    cuts |= set(int(x) for x in rng.integers(1, size, 24))
    for n in sorted(c for c in cuts if 0 < c < size):
        from_bytes(f"truncated-{n}", good[:n])
    for i in range(80):
        b = bytearray(good)
        k = int(rng.integers(1, 9))
        at = int(rng.integers(0, size - k))
        b[at:at + k] = rng.integers(0, 256, k, dtype=np.uint8).tobytes()
        if bytes(b) != good:
            from_bytes(f"bytes-{at}x{k}", bytes(b))
    n_pages = size // page
    for p in range(n_pages):
        b = bytearray(good)
        b[p * page:(p + 1) * page] = bytes(page)
        from_bytes(f"page-{p + 1}-zeroed", bytes(b))
        b[p * page:(p + 1) * page] = rng.integers(0, 256, page, dtype=np.uint8).tobytes()
        from_bytes(f"page-{p + 1}-random", bytes(b))
    for p, q in ((1, 2), (2, n_pages - 1), (0, n_pages - 1)):
        b = bytearray(good)
        b[p * page:(p + 1) * page], b[q * page:(q + 1) * page] = good[q * page:(q + 1) * page], good[p * page:(p + 1) * page]
        from_bytes(f"pages-{p + 1}-{q + 1}-swapped", bytes(b))
    from_bytes("page-appended", good + bytes(page))
    for name, text in _setup_cases(setup):
        from_sql(name, "UPDATE assets SET setup = ?", (text,))
        if name in ("setup-not-json", "setup-carriers-dup", "setup-key-changed"):
            from_sql(name + "-stale-check", "UPDATE assets SET setup = ?", (text,), fix_checks=False)
    from_sql("setup-not-utf8", "UPDATE assets SET setup = CAST(X'7b22ff' AS TEXT)")
    from_sql("setup-blob", "UPDATE assets SET setup = X'7b7d'")
    nb = (n_carriers + 7) // 8
    for n in sorted({0, 1, nb - 1, nb + 1, 1000}):
        from_sql(f"codeword-{n}-bytes", "UPDATE copies SET codeword = ? WHERE rowid = 1", (bytes(n),))
    from_sql("codeword-text", "UPDATE copies SET codeword = 'abc' WHERE rowid = 2")
    from_sql("codeword-changed-stale-check", "UPDATE copies SET codeword = ? WHERE rowid = 1", (bytes(nb),),
             fix_checks=False)
    if n_carriers % 8:
        from_sql("codeword-padding", "UPDATE copies SET codeword = ? WHERE rowid = 1", (b"\xff" * nb,))
    for name, sql in (("copy-id-empty", "UPDATE copies SET copy_id = '' WHERE rowid = 1"),
                      ("copy-id-blob", "UPDATE copies SET copy_id = X'00' WHERE rowid = 1"),
                      ("copy-id-not-utf8", "UPDATE copies SET copy_id = CAST(X'61ff' AS TEXT) WHERE rowid = 1"),
                      ("copy-asset-missing", "UPDATE copies SET asset_id = 999 WHERE rowid = 1"),
                      ("copy-path-blob", "UPDATE copies SET path = X'2f' WHERE rowid = 1"),
                      ("copy-created-blob", "UPDATE copies SET created = X'01' WHERE rowid = 1"),
                      ("copy-row-check-null", "UPDATE copies SET row_check = 'x' WHERE rowid = 1"),
                      ("asset-sha-bad", "UPDATE assets SET source_sha256 = 'xyz'"),
                      ("asset-n-carriers-0", "UPDATE assets SET n_carriers = 0"),
                      ("asset-n-carriers-plus1", f"UPDATE assets SET n_carriers = {n_carriers + 1}"),
                      ("asset-n-carriers-text", "UPDATE assets SET n_carriers = 'x'"),
                      ("asset-n-carriers-huge", "UPDATE assets SET n_carriers = 1000000000000"),
                      ("asset-name-blob", "UPDATE assets SET source_name = X'ff'"),
                      ("asset-path-blob", "UPDATE assets SET original_path = X'2f'"),
                      ("asset-check-bad", "UPDATE assets SET row_check = 'x'"),
                      ("meta-version-3", "UPDATE meta SET value = '3' WHERE name = 'schema_version'"),
                      ("meta-format-gone", "DELETE FROM meta WHERE name = 'format'"),
                      ("meta-extra-row", "INSERT INTO meta VALUES ('x', 'y')"),
                      ("table-extra", "CREATE TABLE extra(x)"),
                      ("table-copies-dropped", "DROP TABLE copies"),
                      ("column-added", "ALTER TABLE copies ADD COLUMN extra TEXT"),
                      ("column-renamed", "ALTER TABLE copies RENAME COLUMN path TO where_written"),
                      ("user-version-7", "PRAGMA user_version = 7"),
                      ("user-version-0", "PRAGMA user_version = 0"),
                      ("application-id-0", "PRAGMA application_id = 0")):
        from_sql(name, sql, fix_checks=not name.endswith("check-bad") and not name.endswith("check-null"))
    return cases


def foreign_cases():
    """[(name, builder(dir) -> path)] of files and folders that are not meshmark registries."""
    cases = []

    def raw(name, data):
        cases.append((name, _bytes_builder(data)))

    def sqlite(name, script, wal=False):
        def build(d):
            p = os.path.join(d, "r.sqlite")
            db = sqlite3.connect(p, isolation_level=None)
            if wal:
                db.execute("PRAGMA journal_mode = wal")
            db.executescript(script)
            db.close()
            return p
        cases.append((name, build))

    raw("empty-file", b"")
    raw("one-byte", b"\0")
    raw("text", b"hello, this is not a database\n" * 40)
    raw("random", np.random.default_rng(5).integers(0, 256, 8192, dtype=np.uint8).tobytes())
    raw("obj-mesh", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    raw("keyfile-json", json.dumps({"format": "meshmark-keyfile", "version": 3}).encode())
    raw("gzip", gzip.compress(b"SQLite format 3\0" * 100))
    raw("sqlite-magic-only", b"SQLite format 3\0")
    raw("sqlite-magic-garbage", b"SQLite format 3\0" + bytes(range(256)) * 20)
    sqlite("app-db", "CREATE TABLE users(id INTEGER PRIMARY KEY, name TEXT); INSERT INTO users VALUES (1, 'ann');")
    sqlite("app-db-with-id", "PRAGMA application_id = 305419896; CREATE TABLE t(x); INSERT INTO t VALUES (1);")
    sqlite("app-db-user-version", "PRAGMA user_version = 2; CREATE TABLE t(x);")
    sqlite("app-db-meta", "CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT); INSERT INTO meta VALUES ('schema_version', '1');")
    sqlite("app-db-lookalike", "CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT); "
           "INSERT INTO meta VALUES ('schema_version', '2'); CREATE TABLE assets(a); CREATE TABLE copies(b);")
    sqlite("app-db-assets-copies", "CREATE TABLE assets(asset_id, setup); CREATE TABLE copies(copy_id);"
           "INSERT INTO assets VALUES (1, '{}');")
    sqlite("app-db-wal", "CREATE TABLE t(x); INSERT INTO t VALUES (1);", wal=True)
    sqlite("app-db-empty", "CREATE TABLE t(x); DROP TABLE t;")
    sqlite("app-db-big", "CREATE TABLE t(x); WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i+1 FROM c LIMIT 3000) "
           "INSERT INTO t SELECT hex(randomblob(40)) FROM c;")

    def folder(d):
        p = os.path.join(d, "r.sqlite")
        os.mkdir(p)
        return p
    cases.append(("folder", folder))

    def link_to_folder(d):
        os.mkdir(os.path.join(d, "sub"))
        p = os.path.join(d, "r.sqlite")
        os.symlink(os.path.join(d, "sub"), p)
        return p
    cases.append(("symlink-to-folder", link_to_folder))

    def dangling(d):
        p = os.path.join(d, "r.sqlite")
        os.symlink(os.path.join(d, "nowhere"), p)
        return p
    cases.append(("dangling-symlink", dangling))

    def fifo(d):
        p = os.path.join(d, "r.sqlite")
        os.mkfifo(p)
        return p
    cases.append(("fifo", fifo))
    return cases


def concurrent_run(src, folder, n=8) -> dict:
    """Two ``meshmark issue --copies n`` processes started together on one new registry: their exit
    statuses, the ids recorded, and whether each copy file traces to its own id (shared with
    bench/registry_concurrency.py). The original is copied into ``folder`` and removed before
    tracing (blind tracing: fast; the registry and its locking are the same)."""
    reg = os.path.join(folder, "r.sqlite")
    src = shutil.copy(src, os.path.join(folder, os.path.basename(str(src))))
    procs = [subprocess.Popen([sys.executable, "-m", "meshmark.cli", "issue", str(src), os.path.join(folder, f"o{k}"),
                               "--copies", str(n), "--key", "owner", "--registry", reg, "--json"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for k in range(2)]
    res = [p.communicate(timeout=600) for p in procs]
    codes = [p.returncode for p in procs]
    os.remove(src)
    files = {}
    for (out, _), rc in zip(res, codes):
        if rc == 0:
            files.update({c["id"]: c["path"] for c in json.loads(out)["copies"]})
    with Registry(reg, create=False) as r:
        ids = sorted(c for aid, _, _ in r.assets() for c in r.copy_ids(aid))
    traced = {cid: tracing.trace(meshmark.read_mesh(p), registry=reg)["copy"] for cid, p in files.items()}
    return {"codes": codes, "errors": [e[-300:] for _, e in res if e.strip()], "ids": ids, "traced": traced}
