"""Registries that know they are registries (meshmark.watermark.registry): damaged and foreign
files, wrong keys, failed and concurrent issues, per-asset copy ids, version-1 migration.

Each CLI case runs in a child process: forked after import (cheap) for the corruption sweep, and a
sample through real ``python -m meshmark.cli`` subprocesses."""
import hashlib
import json
import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time

import numpy as np
import pytest

import meshmark
import meshmark.cli
from meshmark import MeshError
from meshmark.watermark import tracing
from meshmark.watermark.registry import APP_ID, Registry

from conftest import shared_mesh
from registry_cases import concurrent_run, damaged_cases, foreign_cases

MESH = "classic/cow.obj"
OK_MESSAGES = ("not a meshmark registry", "damaged registry", "schema version", "is a folder")


def _cli(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "meshmark.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def _forked(args, timeout=120):
    """(exit status, stdout, stderr) of ``meshmark ARGS`` run in a forked child of this process."""
    out, err = tempfile.TemporaryFile("w+"), tempfile.TemporaryFile("w+")
    pid = os.fork()
    if pid == 0:  # the child: never returns into pytest
        code = 99
        try:
            sys.stdout, sys.stderr = out, err
            os.dup2(err.fileno(), 2)
            try:
                meshmark.cli.main.main(args=[str(a) for a in args], prog_name="meshmark")
                code = 0
            except SystemExit as e:
                code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
        except BaseException:
            import traceback
            traceback.print_exc(file=err)
        finally:
            out.flush()
            err.flush()
            os._exit(code)
    deadline = time.monotonic() + timeout
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, 9)
            os.waitpid(pid, 0)
            raise AssertionError(f"meshmark {args} ran past {timeout} s")
        time.sleep(0.005)
    out.seek(0)
    err.seek(0)
    return os.waitstatus_to_exitcode(status), out.read(), err.read()


def _sha(path) -> str:
    return hashlib.sha256(open(path, "rb").read()).hexdigest() if os.path.isfile(path) else "-"


def _listing(d):
    return sorted(os.listdir(d))


@pytest.fixture(scope="module")
def issued(tmp_path_factory):
    """A registry with 3 real copies of the cow and 300 more recorded codewords (more pages to damage).
    The original is removed after issuing: trace is blind (fast), the registry's checks are the same."""
    d = tmp_path_factory.mktemp("issued")
    reg = d / "r.sqlite"
    shutil.copy(shared_mesh(MESH), d / "cow.obj")
    e = _cli("issue", d / "cow.obj", d / "copies", "--copies", "3", "--key", "owner", "--registry", reg)
    assert e.returncode == 0, e.stderr
    os.remove(d / "cow.obj")
    with Registry(reg) as r:
        (aid, setup, C), = r.assets()
        r.begin()
        rng = np.random.default_rng(3)
        r.add_copies(aid, [(f"x{i:03d}", np.packbits(rng.integers(0, 2, C)).tobytes(), None) for i in range(300)])
        r.commit()
    copy = d / "copies" / "cow-0002.obj"
    return {"dir": d, "reg": reg, "good": reg.read_bytes(), "setup": setup, "C": C, "copy": copy,
            "copies": sorted((d / "copies").iterdir())}


def test_registry_is_marked_private_and_traces(issued):
    reg = issued["reg"]
    assert os.stat(reg).st_mode & 0o777 == 0o600
    db = sqlite3.connect(reg)
    assert db.execute("PRAGMA application_id").fetchone()[0] == APP_ID
    assert db.execute("PRAGMA user_version").fetchone()[0] == 2
    db.close()
    rc, out, err = _forked(["trace", issued["copy"], "--registry", reg, "--json"])
    assert rc == 0 and json.loads(out)["copy"] == "0002", err
    rc, out, err = _forked(["trace", issued["copy"], "--registry", reg, "--key", "WRONG"])
    assert rc == 2 and "wrong key" in err, (rc, err)
    rc, out, err = _forked(["trace", issued["copy"], "--registry", reg, "--key", "owner", "--json"])
    assert rc == 0 and json.loads(out)["copy"] == "0002"
    assert _sha(reg) == hashlib.sha256(issued["good"]).hexdigest()  # trace never writes


def test_damaged_and_foreign_registries_are_refused(issued, tmp_path):
    """>= 200 damaged or foreign registries: exit 2 naming the problem (or, for a change in bytes
    SQLite never reads, the right copy); never exit 1 ("none") or 3, never a traceback; trace never
    changes the file, and issue into a foreign file neither changes it nor writes a copy."""
    damaged = damaged_cases(issued["good"], issued["setup"], issued["C"])
    foreign = foreign_cases()
    assert len(damaged) + len(foreign) >= 200
    tally, unharmed = {"refused": 0, "unharmed": 0}, []
    for kind, cases in (("damaged", damaged), ("foreign", foreign)):
        for name, build in cases:
            d = tmp_path / f"{kind}-{name}"
            d.mkdir()
            path = build(str(d))
            before, files = _sha(path), _listing(d)
            rc, out, err = _forked(["trace", issued["copy"], "--registry", path, "--json"])
            what = f"{kind} {name}: exit {rc}, {err.strip()[-300:]}"
            assert rc in (0, 2) and "Traceback" not in err and "internal error" not in err, what
            if rc == 2:
                assert any(m in err for m in OK_MESSAGES), what
                tally["refused"] += 1
            else:  # a change SQLite and meshmark never read: the registry still answers right
                assert kind == "damaged" and json.loads(out)["copy"] == "0002", what
                tally["unharmed"] += 1
                unharmed.append(name)
            assert _sha(path) == before and _listing(d) == files, f"{what}: trace changed the file"
            if kind == "foreign":
                rc, out, err = _forked(["issue", issued["copy"], d / "out", "--copies", "1", "--key", "k",
                                        "--registry", path])
                assert rc == 2 and any(m in err for m in OK_MESSAGES), f"issue into {name}: {rc} {err}"
                assert _sha(path) == before and _listing(d) == files, f"issue changed foreign {name}"
    print(f"\n{len(damaged)} damaged + {len(foreign)} foreign registries: {tally}; unharmed: {', '.join(unharmed)}")
    assert tally["refused"] >= 190


def test_real_subprocess_sample(issued, tmp_path):
    cases = dict(damaged_cases(issued["good"], issued["setup"], issued["C"]) + foreign_cases())
    for name in ("empty-file", "app-db", f"truncated-{len(issued['good']) - 1000}", "setup-not-json", "folder",
                 "codeword-1-bytes"):
        d = tmp_path / name
        d.mkdir()
        path = cases[name](str(d))
        before = _sha(path)
        e = _cli("trace", issued["copy"], "--registry", path)
        assert e.returncode == 2 and any(m in e.stderr for m in OK_MESSAGES), (name, e.returncode, e.stderr)
        assert _sha(path) == before and _listing(d) == ["r.sqlite"]


def test_failed_issue_records_nothing(issued, tmp_path):
    src = shared_mesh(MESH)
    reg = tmp_path / "r.sqlite"
    reg.write_bytes(issued["good"])
    os.chmod(reg, 0o600)
    good = _sha(reg)
    out = tmp_path / "copies"
    ids = tmp_path / "ids.csv"
    ids.write_text("id\nann\nx/y\n")
    rc, _, err = _forked(["issue", src, out, "--ids", ids, "--key", "owner", "--registry", reg])
    assert rc == 2 and "--ids line 3" in err and "file name" in err, err
    ids.write_bytes(b"ann\n\xff\xfe\n")
    rc, _, err = _forked(["issue", src, out, "--ids", ids, "--key", "owner", "--registry", reg])
    assert rc == 2 and "not UTF-8" in err, err
    rc, _, err = _forked(["issue", src, out, "--copies", "100000000", "--key", "owner", "--registry", reg])
    assert rc == 2 and "100000" in err.replace(",", ""), err
    out.mkdir()
    (out / "cow-0004.obj").write_text("mine")  # the next number of the asset
    rc, _, err = _forked(["issue", src, out, "--copies", "2", "--key", "owner", "--registry", reg])
    assert rc == 2 and "cow-0004.obj exists" in err, err
    assert _sha(reg) == good and _listing(out) == ["cow-0004.obj"]

    class Failing:
        def __init__(self):
            self.n = 0

        def write(self, cid, V):
            self.n += 1
            if self.n == 2:
                raise MeshError("disk full")
            tmp = out / f".tmp-{cid}"
            tmp.write_text("x")
            return [(str(tmp), str(out / f"cow-{cid}.obj"))]
    with pytest.raises(MeshError, match="disk full"):
        tracing.issue(meshmark.read_mesh(src), key="owner", registry=reg, ids=["p", "q"], sink=Failing())
    assert _listing(out) == ["cow-0004.obj"]
    with Registry(reg, create=False) as r:
        assert r.n_copies() == 303 and "p" not in r.copy_ids(1)


def test_copy_ids_are_per_asset_and_version_1_is_migrated(issued, tmp_path):
    """The same recipient label for two assets; a version-1 registry (global ids, no application id)
    is read as it is by trace and migrated by the next issue."""
    reg = tmp_path / "v1.sqlite"
    db = sqlite3.connect(tmp_path / "v1.sqlite")  # the registry issued, rewritten in the version-1 schema
    db.executescript("""
        CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT); INSERT INTO meta VALUES ('schema_version', '1');
        CREATE TABLE assets(asset_id INTEGER PRIMARY KEY, source_sha256 TEXT UNIQUE NOT NULL, source_name TEXT,
            setup TEXT NOT NULL, n_carriers INTEGER NOT NULL, created TEXT, original_path TEXT, original_resolved TEXT);
        CREATE TABLE copies(copy_id TEXT PRIMARY KEY, asset_id INTEGER NOT NULL REFERENCES assets(asset_id),
            codeword BLOB NOT NULL, path TEXT, created TEXT);
        CREATE INDEX copies_asset ON copies(asset_id);""")
    old = sqlite3.connect(issued["reg"])
    for r in old.execute("SELECT asset_id, source_sha256, source_name, setup, n_carriers, created, original_path, "
                         "original_resolved FROM assets"):
        db.execute("INSERT INTO assets VALUES (?, ?, ?, ?, ?, ?, ?, ?)", r)
    for r in old.execute("SELECT copy_id, asset_id, codeword, path, created FROM copies WHERE copy_id LIKE '000%'"):
        db.execute("INSERT INTO copies VALUES (?, ?, ?, ?, ?)", r)
    db.commit()
    db.close()
    old.close()
    before = _sha(reg)
    cow = meshmark.read_mesh(shared_mesh(MESH))
    copy = meshmark.read_mesh(issued["copy"])
    assert tracing.trace(copy, registry=reg)["copy"] == "0002" and _sha(reg) == before
    new = tracing.issue(cow, key="owner", registry=reg, ids=["alice"])
    db = sqlite3.connect(reg)
    assert db.execute("PRAGMA application_id").fetchone()[0] == APP_ID
    assert db.execute("SELECT value FROM meta WHERE name = 'schema_version'").fetchone()[0] == "2"
    db.close()
    assert os.stat(reg).st_mode & 0o777 == 0o600
    teapot = meshmark.read_mesh(shared_mesh("classic/teapot.obj"))
    other = tracing.issue(teapot, key="owner", registry=reg, ids=["alice"])  # the same label, another asset
    a = tracing.trace(new[0][1], cow, registry=reg)
    b = tracing.trace(other[0][1], teapot, registry=reg)
    assert (a["copy"], b["copy"]) == ("alice", "alice") and a["asset_id"] != b["asset_id"]
    assert tracing.trace(copy, registry=reg)["copy"] == "0002"
    with pytest.raises(MeshError, match="already used for this asset: alice"):
        tracing.issue(cow, key="owner", registry=reg, ids=["alice"])


def test_two_concurrent_issues_both_get_their_copies(tmp_path):
    src = shared_mesh(MESH)
    for run in range(3):
        d = tmp_path / f"run{run}"
        d.mkdir()
        r = concurrent_run(src, str(d))
        assert r["codes"] == [0, 0], r["errors"]
        assert r["ids"] == [f"{i:04d}" for i in range(1, 17)]
        assert r["traced"] == {c: c for c in r["ids"]}


def test_issue_gives_up_after_wait_when_another_writer_holds_the_registry(tmp_path):
    """`issue --wait 1` while another process holds the write lock: exit 2 within a few seconds, a
    "busy" message, no copy written and the registry as it was; after the lock is gone it issues."""
    src = shared_mesh(MESH)
    reg = tmp_path / "r.sqlite"
    tracing.issue(meshmark.read_mesh(src), key="owner", registry=str(reg), n_copies=1)
    before = reg.read_bytes()
    holder = sqlite3.connect(str(reg), isolation_level=None)
    holder.execute("BEGIN IMMEDIATE")
    try:
        t0 = time.monotonic()
        r = _cli("issue", src, str(tmp_path / "out"), "--copies", "2", "--key", "owner",
                 "--registry", str(reg), "--wait", "1")
        took = time.monotonic() - t0
    finally:
        holder.execute("ROLLBACK")
        holder.close()
    assert r.returncode == 2, r.stderr
    assert "busy" in r.stderr and "Traceback" not in r.stderr
    assert took < 30  # the 1 s wait plus a process start-up; the default would wait 600 s
    assert reg.read_bytes() == before and not list((tmp_path / "out").glob("*.obj"))
    r = _cli("issue", src, str(tmp_path / "out"), "--copies", "2", "--key", "owner",
             "--registry", str(reg), "--wait", "1")
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (tmp_path / "out").glob("*.obj")) == ["cow-0002.obj", "cow-0003.obj"]
