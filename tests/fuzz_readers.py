"""Fuzzing engine for the mesh readers (used by tests/test_fuzz_readers.py and bench/fuzz_readers.py).

Seeded mutations of real files (../shared/meshes) in every format the readers take: OBJ, ASCII OFF,
binary OFF, ASCII PLY, binary PLY (little/big endian; float, double, int16 and uint8 coordinates;
uchar/int/uint index lists), ASCII and binary STL. Each case is written to a file and read in its
own forked child process (``read_mesh``, and ``mesh_info`` with ``info=True``); the parent classifies the outcome from
the child's wait status and ``wait4`` resource usage:

- ``signal``: the child died of a signal (SIGSEGV, SIGABRT, SIGKILL...), or hung (SIGALRM after 30 s);
- ``exception``: an exception other than MeshError (the traceback is kept);
- ``oom``: a MeshError from an allocation failure (the child runs under an RLIMIT_AS cap, so a
  balloon fails fast instead of taking the machine down);
- ``utf8``: a MeshError whose message is not valid UTF-8;
- ``memory``: the child's peak RSS grew by more than 20 x the file size + 64 MB over a forked child
  that does nothing (the baseline);
- otherwise ``ok`` (read) or ``meshError``.

Run as a script: ``python tests/fuzz_readers.py --cases 2000 --seed 0`` prints a JSON summary; the
files of failing cases are kept in ``--keep`` for attribution.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import signal
import struct
import sys
import tempfile
import time
import traceback

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)  # fuzz_gltf, gltf_assets
SHARED = os.path.join(os.environ.get("MESHMARK_SHARED", os.path.join(HERE, "..", "..", "shared")), "meshes")
MB = 1 << 20
BUDGET_FACTOR, BUDGET_EXTRA = 20, 64 * MB

# Small real files (fast cases) of each on-disk kind; the PLY, binary OFF and ASCII STL variants
# are written from real meshes below.
REAL_FILES = ["corpus/c3d_woody.obj", "classic/suzanne.obj", "corpus/libigl_decimated-knight.off",
              "corpus/vhacd_helix.off", "corpus/thingi10k_130976.stl", "corpus/thingi10k_37885.stl"]

HOSTILE = [b"-1", b"0", b"1", b"2", b"3", b"2147483647", b"2147483648", b"4294967295", b"-2147483649",
           b"99999999999", b"1000000000", b"1e308", b"1e-308", b"-1e308", b"nan", b"inf", b"-inf", b"1.5",
           b"0x10", b"+3", b"", b"3.", b"1e9", b"\xff", b"\xc3\x28", b"18446744073709551616", b"-0", b"00000003"]
PLY_TYPES = [b"char", b"uchar", b"short", b"ushort", b"int", b"uint", b"float", b"double", b"int8", b"uint8",
             b"int16", b"uint16", b"int32", b"uint32", b"float32", b"float64", b"list uchar int", b"list int float",
             b"list uint uint", b"float128", b"string"]
PLY_LINES = [b"property int x", b"property list uchar float z", b"element vertex 1000000000", b"element face 2147483647",
             b"property float x", b"comment \xff\xfe", b"element vertex 1e308", b"format ascii 1.0",
             b"format binary_big_endian 1.0", b"end_header", b"property list uint int vertex_indices", b"element edge 5",
             b"property uchar red", b"obj_info x"]
NUM = re.compile(rb"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def _ply_bytes(V, F, fmt, vtype="float", itype="int", ctype="uchar"):
    """A PLY file of the real mesh (V, F triangles) with the given types (big-endian for binary_big_endian)."""
    np_t = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4",
            "float": "f4", "double": "f8"}
    if vtype in ("char", "uchar", "short", "ushort", "int", "uint"):
        lo, hi = np.iinfo(np_t[vtype]).min, np.iinfo(np_t[vtype]).max
        span = np.ptp(V, axis=0).max() or 1.0
        V = np.round((V - V.min(0)) / span * min(hi - lo, 30000) + max(lo, -15000))
    head = (f"ply\nformat {fmt} 1.0\ncomment fuzz base\nelement vertex {len(V)}\nproperty {vtype} x\n"
            f"property {vtype} y\nproperty {vtype} z\nelement face {len(F)}\n"
            f"property list {ctype} {itype} vertex_indices\nend_header\n").encode()
    if fmt == "ascii":
        fmtv = "%d %d %d" if np_t[vtype][0] in "iu" else "%.9g %.9g %.9g"
        body = "\n".join(fmtv % tuple(v) for v in V) + "\n" + "\n".join("3 %d %d %d" % tuple(f) for f in F) + "\n"
        return head + body.encode()
    e = ">" if fmt == "binary_big_endian" else "<"
    rec = np.zeros(len(F), dtype=[("n", e + np_t[ctype]), ("i", e + np_t[itype], 3)])
    rec["n"], rec["i"] = 3, F
    return head + np.asarray(V, e + np_t[vtype]).tobytes() + rec.tobytes()


def _binary_off(V, F, big):
    e = ">" if big else "<"
    rec = np.zeros(len(F), dtype=[("n", e + "i4"), ("i", e + "i4", 3), ("c", e + "i4")])
    rec["n"], rec["i"] = 3, F
    return (b"OFF BINARY\n" + struct.pack(e + "3i", len(V), len(F), 0) + np.asarray(V, e + "f4").tobytes()
            + rec.tobytes())


def make_bases(workdir: str, large: bool = False) -> list[dict]:
    """The seed files: real files as they are, plus real meshes written in the other encodings."""
    import meshmark
    files = list(REAL_FILES) + (["classic/horse.ply", "classic/bunny.obj", "classic/elephant.off"] if large else [])
    bases = []
    for rel in files:
        p = os.path.join(SHARED, rel)
        assert os.path.isfile(p), f"shared mesh {p} is missing: the fuzz test needs ../shared/meshes beside the repo"
        with open(p, "rb") as f:
            bases.append({"name": rel, "ext": rel.rsplit(".", 1)[1], "data": f.read()})
    for rel in ["corpus/c3d_woody.obj", "classic/suzanne.obj"]:
        m = meshmark.read_mesh(os.path.join(SHARED, rel))
        t = meshmark.Mesh(m.V, m.triangles)
        V, F = np.asarray(t.V), np.asarray(t.F)
        short = rel.rsplit("/", 1)[1].split(".")[0]
        for fmt, vt, it, ct in [("ascii", "float", "int", "uchar"), ("binary_little_endian", "float", "int", "uchar"),
                                ("binary_big_endian", "double", "uint", "uchar"), ("binary_little_endian", "short", "int", "uint"),
                                ("binary_little_endian", "uchar", "int", "ushort"), ("ascii", "int", "int", "uchar")]:
            bases.append({"name": f"{short} as {fmt} {vt}/{ct} {it}", "ext": "ply", "data": _ply_bytes(V, F, fmt, vt, it, ct)})
        bases.append({"name": f"{short} as binary OFF (big)", "ext": "off", "data": _binary_off(V, F, True)})
        bases.append({"name": f"{short} as binary OFF (little)", "ext": "off", "data": _binary_off(V, F, False)})
        stl = os.path.join(workdir, f"{short}-ascii.stl")
        meshmark.write_mesh(stl, t, binary=False, precision=9)
        with open(stl, "rb") as f:
            bases.append({"name": f"{short} as ASCII STL", "ext": "stl", "data": f.read()})
        os.remove(stl)
    return bases


def _header_end(data: bytes) -> int:
    i = data.find(b"end_header")
    if i >= 0:
        return i + 11
    return min(len(data), 400)


def mutate(data: bytes, rng: np.random.Generator) -> tuple[bytes, str]:
    """1-3 seeded mutations; returns the bytes and a description of what was done."""
    b = bytearray(data)
    done = []
    for _ in range(int(rng.choice([1, 2, 3], p=[0.6, 0.3, 0.1]))):
        op = int(rng.integers(0, 9))
        n = len(b)
        if n == 0:
            b = bytearray(rng.integers(0, 256, 16, dtype=np.uint8).tobytes())
            done.append("random 16 bytes")
            continue
        hdr = _header_end(bytes(b))
        if op == 0:  # flip bytes
            k = int(rng.integers(1, 9))
            at = rng.integers(0, n, k)
            for a in at:
                b[a] = int(rng.integers(0, 256))
            done.append(f"set {k} bytes")
        elif op == 1:  # truncate
            cut = int(rng.integers(0, n))
            b = b[:cut]
            done.append(f"truncate at {cut}")
        elif op == 2:  # delete a chunk
            a = int(rng.integers(0, n))
            L = int(rng.integers(1, max(2, min(n - a, 200))))
            del b[a:a + L]
            done.append(f"delete {L} at {a}")
        elif op == 3:  # duplicate a chunk / insert random bytes
            a = int(rng.integers(0, n))
            L = int(rng.integers(1, 64))
            chunk = bytes(b[a:a + L]) if rng.random() < 0.5 else rng.integers(0, 256, L, dtype=np.uint8).tobytes()
            at = int(rng.integers(0, n))
            b[at:at] = chunk
            done.append(f"insert {L} at {at}")
        elif op in (4, 5):  # replace a number (in the header half the time) with a hostile one
            region = bytes(b[:hdr]) if (op == 4 and hdr < n) else bytes(b[: min(n, 200000)])
            ms = list(NUM.finditer(region))
            if not ms:
                continue
            m = ms[int(rng.integers(0, len(ms)))]
            new = HOSTILE[int(rng.integers(0, len(HOSTILE)))]
            b[m.start():m.end()] = new
            done.append(f"number {m.group()!r} at {m.start()} -> {new!r}")
        elif op == 6:  # header line edit (PLY types, inserted/removed/swapped lines)
            head = bytes(b[:hdr])
            lines = head.split(b"\n")
            k = int(rng.integers(0, 4))
            i = int(rng.integers(0, len(lines)))
            if k == 0:
                ts = [m for m in re.finditer(rb"\b(char|uchar|short|ushort|int|uint|float|double|int8|uint8|int16|uint16|int32|uint32|float32|float64)\b", lines[i])]
                if ts:
                    t = ts[int(rng.integers(0, len(ts)))]
                    lines[i] = lines[i][:t.start()] + PLY_TYPES[int(rng.integers(0, len(PLY_TYPES)))] + lines[i][t.end():]
            elif k == 1:
                del lines[i]
            elif k == 2:
                lines.insert(i, PLY_LINES[int(rng.integers(0, len(PLY_LINES)))])
            else:
                j = int(rng.integers(0, len(lines)))
                lines[i], lines[j] = lines[j], lines[i]
            b[:hdr] = b"\n".join(lines)
            done.append(f"header line edit {k} at line {i}")
        elif op == 7:  # overwrite a binary word with a hostile integer
            at = int(rng.integers(max(0, hdr - 12) if hdr < n else 0, n))
            v = [0, 1, 3, 255, 2**31 - 1, 2**31, 2**32 - 1, 2**30, 1000000000, 0x7F800000, 0xFFC00000][int(rng.integers(0, 11))]
            fmt, mask = [("<I", 0xFFFFFFFF), (">I", 0xFFFFFFFF), ("<H", 0xFFFF), ("B", 0xFF)][int(rng.integers(0, 4))]
            w = struct.pack(fmt, v & mask)
            b[at:at + len(w)] = w
            done.append(f"word {v:#x} at {at}")
        else:  # non-UTF-8 / control bytes into the header or the first lines
            at = int(rng.integers(0, max(1, min(hdr, n))))
            junk = [b"\xff", b"\xfe\xff", b"\x00", b"\xc3", b"\xed\xa0\x80", b"\r", b"\t\x0b"][int(rng.integers(0, 7))]
            b[at:at] = junk
            done.append(f"bytes {junk!r} at {at}")
    return bytes(b), "; ".join(done) or "unchanged"


_INFO = [False]  # also run mesh_info on the meshes that read (set by run)


def _vm_size() -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


def _child(path: str, w: int, cap: int) -> None:
    import meshmark
    code, msg = 0, ""
    try:
        signal.alarm(30)
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        try:
            m = meshmark.read_mesh(path)
            if _INFO[0]:
                meshmark.mesh_info(m)
        except meshmark.MeshError as e:
            msg = str(e)
            code = 4 if "out of memory" in msg else 1
            try:
                msg.encode("utf-8")
            except UnicodeEncodeError:
                code, msg = 5, repr(msg)
        except MemoryError:
            code, msg = 4, "MemoryError"
        except BaseException:
            code, msg = 3, traceback.format_exc()
    except BaseException:
        code, msg = 3, traceback.format_exc()
    try:
        os.write(w, msg.encode("utf-8", "backslashreplace")[:4000])
    finally:
        os._exit(code)


def _run_child(path: str, cap: int):
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(r)
        _child(path, w, cap)
    os.close(w)
    chunks = []
    while True:
        c = os.read(r, 65536)
        if not c:
            break
        chunks.append(c)
    os.close(r)
    _, status, ru = os.wait4(pid, 0)
    return status, ru.ru_maxrss * 1024, b"".join(chunks).decode("utf-8", "replace")


def _noop_child() -> int:
    pid = os.fork()
    if pid == 0:
        os._exit(0)
    _, _, ru = os.wait4(pid, 0)
    return ru.ru_maxrss * 1024


FORMATS = ("obj", "off", "ply", "stl")  # the default campaign; glTF: formats=("glb", "gltf") (tests/fuzz_gltf.py)


def run(cases: int, seed: int, keep: str | None = None, large: bool = False, progress: bool = False,
        info: bool = False, formats=FORMATS) -> dict:
    import meshmark
    _INFO[0] = info
    work = tempfile.mkdtemp(prefix="meshmark-fuzz-")
    try:
        bases = [b for b in make_bases(work, large=large) if b["ext"] in formats] if set(formats) & set(FORMATS) else []
        if set(formats) & {"glb", "gltf"}:
            import fuzz_gltf
            bases += [b for b in fuzz_gltf.bases(SHARED) if b["ext"] in formats]
        for bs in bases:  # every base must read (they are real meshes); also warms the imports up
            p = os.path.join(work, "base." + bs["ext"])
            with open(p, "wb") as f:
                f.write(bs["data"])
            meshmark.mesh_info(meshmark.read_mesh(p))
        baseline = max(_noop_child() for _ in range(3))
        rng = np.random.default_rng(seed)
        counts: dict = {}
        per_format: dict = {}
        failures = []
        worst = {"ratio": 0.0}
        peak = {"budget_fraction": 0.0}
        t0 = time.time()
        by_ext: dict = {}
        for bs in bases:
            by_ext.setdefault(bs["ext"], []).append(bs)
        exts = sorted(by_ext)
        for i in range(cases):  # the formats in turn, and the bases of a format in turn
            group = by_ext[exts[i % len(exts)]]
            bs = group[(i // len(exts)) % len(group)]
            if bs["ext"] in ("glb", "gltf"):
                data, what = fuzz_gltf.mutate(bs["data"], bs["ext"], rng, mutate)
            else:
                data, what = mutate(bs["data"], rng)
            path = os.path.join(work, f"case{i}.{bs['ext']}")
            with open(path, "wb") as f:
                f.write(data)
            budget = BUDGET_FACTOR * len(data) + BUDGET_EXTRA
            cap = _vm_size() + budget + 1024 * MB
            status, maxrss, msg = _run_child(path, cap)
            grew = max(0, maxrss - baseline)
            if os.WIFSIGNALED(status):
                kind = "hang" if os.WTERMSIG(status) == signal.SIGALRM else "signal"
                msg = f"signal {os.WTERMSIG(status)}"
            else:
                kind = {0: "ok", 1: "meshError", 3: "exception", 4: "oom", 5: "utf8"}.get(os.WEXITSTATUS(status), "exit")
            if kind in ("ok", "meshError") and grew > budget:
                kind = "memory"
            counts[kind] = counts.get(kind, 0) + 1
            per_format[bs["ext"]] = per_format.get(bs["ext"], 0) + 1
            if grew / budget > peak["budget_fraction"]:
                peak = {"budget_fraction": round(grew / budget, 4), "grew_bytes": grew, "file_bytes": len(data),
                        "case": i, "base": bs["name"], "outcome": kind}
            if len(data) >= 100000 and grew / len(data) > worst["ratio"]:
                worst = {"ratio": grew / len(data), "grew_bytes": grew, "file_bytes": len(data), "case": i}
            if kind not in ("ok", "meshError"):
                kept = None
                if keep:
                    os.makedirs(keep, exist_ok=True)
                    kept = os.path.join(keep, f"case{i}-{kind}.{bs['ext']}")
                    shutil.copyfile(path, kept)
                failures.append({"case": i, "kind": kind, "base": bs["name"], "mutation": what,
                                 "file_bytes": len(data), "grew_bytes": grew, "message": msg[-1500:], "kept": kept})
            os.remove(path)
            if progress and (i + 1) % 500 == 0:
                print(f"{i + 1}/{cases} cases, {time.time() - t0:.0f} s, {counts}", file=sys.stderr, flush=True)
        return {"cases": cases, "seed": seed, "bases": len(bases), "per_format": per_format, "counts": counts,
                "baseline_rss_bytes": baseline, "largest_growth_per_byte_of_files_over_100kB": worst, "closest_to_budget": peak, "seconds": round(time.time() - t0, 1),
                "failures": failures}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--keep", default=None, help="folder for the files of failing cases")
    ap.add_argument("--large", action="store_true", help="also mutate the Horse PLY, Bunny OBJ and Elephant OFF")
    ap.add_argument("--info", action="store_true", help="also run mesh_info on every mesh that reads")
    ap.add_argument("--progress", action="store_true")
    ap.add_argument("--formats", default=",".join(FORMATS), help="comma-separated: obj,off,ply,stl,glb,gltf")
    a = ap.parse_args(argv)
    summary = run(a.cases, a.seed, keep=a.keep, large=a.large, progress=a.progress, info=a.info,
                  formats=tuple(a.formats.split(",")))
    print(json.dumps(summary, indent=1))
    return 0 if not summary["failures"] else 1


if __name__ == "__main__":
    sys.exit(main())
