"""Keyfile mutation engine (issue 23; used by tests/test_keyfile_mutations.py).

Real keyfiles are written by ``meshmark.watermark.embed`` for every method (laplacian with the
default and the thesis carrier and ``thesis_exact``, radial, cho-mean, cho-variance), text and bit
payloads, the keyed code and the convolutional code, with and without the stored key, as version 3
(tagged) and as the untagged versions 2 and 1 that older meshmark wrote. Each is mutated
deterministically (:func:`mutations`): fields dropped, given hostile values (types, huge numbers,
non-ASCII, lone surrogates, nesting), swapped, ``lo > hi``, the method and version switched, the key
and tag changed, NaN/Infinity literals, truncated bytes, flipped and random bytes, and ``--key``
given on the command line with a lone surrogate or non-ASCII text.

Every case runs the real CLI, ``meshmark extract MESH --keyfile K [--key ...]``, in its own child:
``os.fork()`` after importing meshmark, ``meshmark.cli.main()`` in the child, exit status and the
child's stdout/stderr back through pipes (``--subprocess N`` also runs N cases through
``python -m meshmark`` and compares). The verdict of each case (:func:`judge`):

- ``exit3``: status 3 (internal error) or anything but 0/1/2; ``traceback``: "Traceback" in the
  output; ``hang``: no answer within 60 s; ``bad_error``: status 2 without a ``meshmark: error:`` line;
- ``false_detect``: status 0 although the file is not the base keyfile's content (compared after
  parsing: field order and spacing do not matter) unless the file is untagged and reads the base's
  method, key and payload (an untagged file cannot show that a value was changed; those cases are
  counted as ``detect_untagged_changed``).

Run as a script: ``python tests/keyfile_fuzz.py --cases 5000 --seed 23`` prints a JSON summary.
"""
from __future__ import annotations

import argparse
import collections
import copy
import gc
import io
import json
import os
import random
import selectors
import signal
import subprocess
import sys
import tempfile
import time
import traceback

HOSTILE = [None, True, False, 0, 1, -1, 2, 3, 0.5, -0.0, 1e-320, 1e300, -1e300, 1.7976931348623157e308,
           2 ** 31, 2 ** 53 + 1, 2 ** 64, 10 ** 40, -(10 ** 40), "", "0", "x", "ownerA\udcff", "\udcff", "\ud800x",
           "ü", "日本語", "\x00", "a" * 5000, [], {}, [1], [[[[]]]], {"a": {"b": 1}}, "NaN", "Infinity"]
LITERALS = ["NaN", "Infinity", "-Infinity", "1e999", "-1e999", "1e-999", "9" * 5000, "0x10", "01", "+1", ".5",
            "1.", "1e", "-", "true", "null", '"1"', "[]", "{}", "1e308", "-0", "4294967296"]
HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.join(os.environ.get("MESHMARK_SHARED", os.path.join(HERE, "..", "..", "shared")), "meshes")
METHODS = ("laplacian", "radial", "cho-mean", "cho-variance")
TIMEOUT = 60.0


# --- bases: real keyfiles -------------------------------------------------------------------------
def build_bases(workdir: str) -> list:
    """[(name, mesh path, keyfile dict, extra CLI args)]: every method and version; extraction of
    each gives status 0 (checked by the caller)."""
    import meshmark
    import meshmark.watermark as W
    mesh = meshmark.read_mesh(os.path.join(SHARED, "classic", "cow.obj"))
    specs = [("lap-auto", dict(method="laplacian", payload="h", key="ownerA")),
             ("lap-thesis-carrier", dict(method="laplacian", payload="0110", key="ownerB", carrier="thesis")),
             ("lap-thesis-exact", dict(method="laplacian", payload="k", key="ownerC", thesis_exact=True)),
             ("radial", dict(method="radial", payload="r", key="ownerD")),
             ("radial-long", dict(method="radial", payload="longer text", key="ownerE")),
             ("cho-mean", dict(method="cho-mean", payload="m", key="ownerF")),
             ("cho-variance", dict(method="cho-variance", payload="v", key="ownerG")),
             ("lap-nokey", dict(method="laplacian", payload="n", key="secretH", store_key=False))]
    bases = []
    for name, kw in specs:
        kw = dict(kw)
        payload = kw.pop("payload")
        if set(payload) <= {"0", "1"}:
            payload = [int(c) for c in payload]
        r = W.embed(mesh, payload=payload, **kw)
        path = os.path.join(workdir, f"{name}.obj")
        meshmark.write_mesh(path, r.V, mesh.F)
        d = json.loads(r.keyfile.to_json())
        extra = ["--key", kw["key"]] if not kw.get("store_key", True) else []
        bases.append((name, path, d, extra))
        if "key" not in d:
            continue
        v2 = {k: v for k, v in d.items() if k != "tag"}
        v2["version"] = 2
        bases.append((name + "-v2", path, v2, extra))
        v1 = {k: v for k, v in v2.items() if k != "weld"}
        v1["version"] = 1
        bases.append((name + "-v1", path, v1, extra))
    return bases


# --- mutations ------------------------------------------------------------------------------------
def _paths(d, prefix=()):
    for k, v in d.items():
        yield prefix + (k,)
        if isinstance(v, dict):
            yield from _paths(v, prefix + (k,))
        elif isinstance(v, list) and v:
            for i in sorted({0, len(v) - 1}):
                yield prefix + (k, i)


def _get(d, path):
    for p in path:
        d = d[p]
    return d


def _set(d, path, value):
    d = copy.deepcopy(d)
    t = d
    for p in path[:-1]:
        t = t[p]
    if value is _DELETE:
        del t[path[-1]]
    else:
        t[path[-1]] = value
    return d


_DELETE = object()


def edit(d: dict, dotted: str, value) -> dict:
    """A copy of the keyfile dict ``d`` with the field at ``dotted`` (e.g. ``"params.alpha"``) set to
    ``value``, or deleted when ``value`` is ``KeyError``."""
    return _set(d, tuple(dotted.split(".")), _DELETE if value is KeyError else value)


def _derived(v):
    """Values close to ``v``: off by one, scaled, as another type."""
    out = []
    if isinstance(v, bool):
        out += [not v, int(v), str(v).lower()]
    elif isinstance(v, int):
        out += [v + 1, v - 1, -v, v * 1000, float(v), str(v), [v], v + 2 ** 32]
    elif isinstance(v, float):
        out += [v * (1 + 1e-12), v * 1.5, -v, v * 1e300, int(v), str(v), [v], v + 1]
    elif isinstance(v, str):
        out += [v + "é", v.upper(), v[:-1], v + "\udcff", v[:1] + "\udcff" + v[1:], v * 3, [v], v[::-1],
                v[:-1] + "é" if v else "é"]
    elif isinstance(v, list):
        out += [v[:-1], v + v[:1], v[::-1], v[1:] + v[:1], [str(x) for x in v[:3]], v[:1] * len(v), []]
    elif isinstance(v, dict):
        out += [list(v.values()), {}, {**v, "extra": 1}, json.dumps(v)]
    return out


def _doc(d, ensure_ascii=True):
    return json.dumps(d, indent=1, ensure_ascii=ensure_ascii).encode("utf-8", "surrogatepass")


def mutations(base: dict, rng: random.Random, others: list) -> list:
    """[(kind, file bytes, extra args or None)] for one base keyfile dict; ``others``: the other
    bases' dicts (for method switches with their parameters)."""
    out = []
    add = lambda kind, d, args=None: out.append((kind, d if isinstance(d, bytes) else _doc(d), args))
    for path in _paths(base):
        name = ".".join(map(str, path))
        v = _get(base, path)
        add(f"drop {name}", _set(base, path, _DELETE))
        for x in HOSTILE + _derived(v):
            add(f"set {name}", _set(base, path, x))
    # the method and its parameters switched; side_info from another method
    for m in METHODS:
        add(f"method {m}", {**base, "method": m})
        for o in others:
            if o["method"] == m:
                add(f"method {m} with its params", {**base, "method": m, "params": o["params"]})
                add(f"side_info of {m}", {**base, "side_info": o["side_info"]})
                break
    # versions
    for ver in (1, 2, 3, 4, 0, -1, "3", 3.0, True, None, 2 ** 70):
        add("version", {**base, "version": ver})
        add("version, no tag", {k: v for k, v in {**base, "version": ver}.items() if k != "tag"})
    # swaps and ordering
    s = base["side_info"]
    if "lo" in s:
        lo, hi = s["lo"], s["hi"]
        for nlo, nhi in [(hi, lo), (hi, hi), (lo, lo), (hi * 1.01, hi), (hi, hi * (1 - 1e-13)), (-1e300, 1e300),
                         (0.0, 0.0), (lo, lo * (1 + 1e-15)), (5e-324, 1e-323), (-hi, -lo)]:
            add("lo/hi", _set(_set(base, ("side_info", "lo"), nlo), ("side_info", "hi"), nhi))
    for a, b in [(("params", "K"), ("coding", "n_coded")), (("key",), ("tag",)), (("params",), ("side_info",)),
                 (("payload",), ("coding",)), (("coding", "info_bits"), ("coding", "n_coded")),
                 (("params", "K"), ("params", "n_thr")), (("payload", "bits"), ("payload", "sha256"))]:
        try:
            va, vb = _get(base, a), _get(base, b)
        except (KeyError, TypeError):
            continue
        add("swap " + ".".join(a) + " " + ".".join(b), _set(_set(base, a, vb), b, va))
    # the key and the tag
    for k in ("ownerA\udcff", "\udcff", "ownerAü", "wrong", "", "日本"):
        add("key", {**base, "key": k})
    if "tag" in base:
        t = base["tag"]
        for nt in (t[:10] + "é" + t[11:], t.upper(), t[:-1], t + "0", "0" * 64, t[:5] + "\udcff" + t[6:],
                   t[::-1], "g" * 64, "ü" * 64):
            add("tag", {**base, "tag": nt})
    # the command line's --key
    for k in ("ownerA\udcff", "\udcff", "ownerAü", "wrong", "", base.get("key", "x") + "\udcff", "\x00"):
        add("--key", base, ["--key", k])
    # text level: literals, bytes
    raw = _doc(base)
    text = raw.decode()
    numbers = [m for m in __import__("re").finditer(r'(?<=: )-?\d+(\.\d+)?([eE][-+]?\d+)?', text)]
    for m in rng.sample(numbers, min(len(numbers), 12)):
        for lit in rng.sample(LITERALS, 6):
            add("literal " + lit[:12], (text[:m.start()] + lit + text[m.end():]).encode())
    for _ in range(12):
        add("truncated", raw[:rng.randrange(len(raw))])
    for _ in range(16):
        b = bytearray(raw)
        for _ in range(rng.choice((1, 1, 2, 5, 20))):
            b[rng.randrange(len(b))] = rng.randrange(256)
        add("flipped bytes", bytes(b))
    for n in (0, 1, 7, 64, 4096):
        add("random bytes", bytes(rng.randrange(256) for _ in range(n)))
    ins = raw.index(b"{") + 1
    for blob in (b'"key": "other", ', b'"method": "radial", ', b'"x": ' + b"[" * 40 + b"]" * 40 + b", ",
                 b'"\\udcff": 1, ', b'"k\xff": 1, ', b'"v": "\xc3\x28", '):
        add("inserted " + blob[:12].decode("latin-1"), raw[:ins] + blob + raw[ins:])
    add("BOM", b"\xef\xbb\xbf" + raw)
    add("UTF-16", text.encode("utf-16"))
    add("latin-1 in strings", _doc(base, ensure_ascii=False).replace(b"meshmark-keyfile", b"meshmark-k\xe9yfile"))
    add("top-level array", b"[" + raw + b"]")
    add("reordered", json.dumps(dict(reversed(list(base.items())))).encode())
    add("compact", json.dumps(base, separators=(",", ":")).encode())
    return out


# --- running one case -----------------------------------------------------------------------------
def _child(argv, wout, werr) -> None:
    """In the forked child: run the CLI, exit with its status (never returns)."""
    code = 98
    try:
        sys.stdin = open(os.devnull)
        sys.stdout = io.TextIOWrapper(os.fdopen(wout, "wb"), encoding="utf-8", errors="strict", line_buffering=True)
        sys.stderr = io.TextIOWrapper(os.fdopen(werr, "wb"), encoding="utf-8", errors="backslashreplace",
                                      line_buffering=True)
        from meshmark.cli import main
        try:
            main(args=argv, prog_name="meshmark")
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except BaseException:  # noqa: BLE001 - escaped the CLI's handler: reported as such
        try:
            traceback.print_exc()
        except BaseException:  # noqa: BLE001
            pass
        code = 97
    finally:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        except BaseException:  # noqa: BLE001
            pass
        os._exit(code)


def _start(argv):
    rout, wout = os.pipe()
    rerr, werr = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(rout)
        os.close(rerr)
        _child(argv, wout, werr)
    os.close(wout)
    os.close(werr)
    return pid, rout, rerr


def run_many(argvs, jobs: int = 2):
    """Yield (index, status, stdout, stderr) of ``meshmark *argv`` for each argv, each in its own
    forked child, at most ``jobs`` at a time; status None on a hang (killed after TIMEOUT)."""
    sel = selectors.DefaultSelector()
    running = {}  # pid -> [index, open fds, out, err, deadline]
    todo = iter(enumerate(argvs))
    exhausted = False
    while running or not exhausted:
        while not exhausted and len(running) < jobs:
            nxt = next(todo, None)
            if nxt is None:
                exhausted = True
                break
            i, argv = nxt
            pid, rout, rerr = _start(argv)
            running[pid] = [i, {rout, rerr}, bytearray(), bytearray(), time.monotonic() + TIMEOUT, rout]
            sel.register(rout, selectors.EVENT_READ, pid)
            sel.register(rerr, selectors.EVENT_READ, pid)
        if not running:
            break
        for k, _ in sel.select(1.0):
            r = running[k.data]
            chunk = os.read(k.fd, 65536)
            if chunk:
                (r[2] if k.fd == r[5] else r[3]).extend(chunk)
            else:
                sel.unregister(k.fd)
                os.close(k.fd)
                r[1].discard(k.fd)
        now = time.monotonic()
        for pid in list(running):
            r = running[pid]
            hung = now > r[4] and r[1]
            if hung:
                os.kill(pid, signal.SIGKILL)
                for fd in r[1]:
                    sel.unregister(fd)
                    os.close(fd)
                r[1].clear()
            if not r[1]:
                _, status = os.waitpid(pid, 0)
                del running[pid]
                code = None if hung else os.waitstatus_to_exitcode(status)
                yield r[0], code, r[2].decode("utf-8", "replace"), r[3].decode("utf-8", "replace")
    sel.close()


def run_fork(argv) -> tuple:
    """(status, stdout, stderr) of ``meshmark *argv`` in a forked child; status None on a hang."""
    return next(run_many([argv], 1))[1:]


def run_subprocess(argv) -> tuple:
    args = [a.encode("utf-8", "surrogateescape") for a in argv]
    r = subprocess.run([sys.executable, "-m", "meshmark", *args], capture_output=True, stdin=subprocess.DEVNULL,
                       timeout=TIMEOUT * 2)
    return r.returncode, r.stdout.decode("utf-8", "replace"), r.stderr.decode("utf-8", "replace")


# --- verdicts -------------------------------------------------------------------------------------
def _semantic(raw: bytes):
    try:
        return json.loads(raw.decode("utf-8"))
    except Exception:  # noqa: BLE001
        return None


def judge(code, out: str, err: str, raw: bytes, base: dict, args, base_args=()) -> str:
    if code is None:
        return "hang"
    if "Traceback" in out or "Traceback" in err:
        return "traceback"
    if code not in (0, 1, 2):
        return "exit3"
    if code == 2 and "meshmark: error:" not in err:
        return "bad_error"
    if code == 0:
        d = _semantic(raw)
        true_key = base.get("key") or (base_args[1] if base_args else None)
        key = (args[1] if args else None) or (d.get("key") if isinstance(d, dict) else None)
        if d == base and key == true_key:
            return "ok"
        if (isinstance(d, dict) and "tag" not in d and d.get("method") == base["method"]
                and d.get("payload") == base["payload"] and key == true_key):
            return "detect_untagged_changed"
        return "false_detect"
    return "ok"


def campaign(n_cases: int, seed: int, n_subprocess: int = 0, workdir: str | None = None, jobs: int = 2) -> dict:
    t0 = time.monotonic()
    own = workdir is None
    workdir = workdir or tempfile.mkdtemp(prefix="keyfile-fuzz-")
    bases = build_bases(workdir)
    import meshmark.cli  # noqa: F401  (imported before forking: each child only runs main())
    rng = random.Random(seed)
    cases = []
    for name, mesh, d, extra in bases:
        others = [o for _, _, o, _ in bases if o["method"] != d["method"]]
        for kind, raw, args in mutations(d, rng, others):
            cases.append((name, mesh, d, extra if args is None else args, kind, raw, extra))
    per_base = collections.Counter(c[0] for c in cases)
    rng.shuffle(cases)
    cases = cases[:n_cases]
    t_built = time.monotonic()
    baseline = {}
    for name, mesh, d, extra in bases:
        p = os.path.join(workdir, f"{name}.json")
        with open(p, "wb") as f:
            f.write(_doc(d))
        baseline[name] = run_fork(["extract", mesh, "--keyfile", p, *extra])[0]
    codes, verdicts, failures, untagged = collections.Counter(), collections.Counter(), [], collections.Counter()
    results = []
    casedir = os.path.join(workdir, "cases")
    os.makedirs(casedir, exist_ok=True)
    argvs = []
    for i, (name, mesh, d, args, kind, raw, extra) in enumerate(cases):
        p = os.path.join(casedir, f"{i}.json")
        with open(p, "wb") as f:
            f.write(raw)
        argvs.append(["extract", mesh, "--keyfile", p, *args])
    gc.collect()
    gc.freeze()  # fewer copy-on-write pages in the children
    for i, code, out, err in run_many(argvs, jobs):
        name, mesh, d, args, kind, raw, extra = cases[i]
        v = judge(code, out, err, raw, d, args, extra)
        codes[str(code)] += 1
        verdicts[v] += 1
        if v == "detect_untagged_changed":
            untagged[kind] += 1
        if v not in ("ok", "detect_untagged_changed"):
            failures.append({"base": name, "kind": kind, "code": code, "stderr": err[-600:], "stdout": out[-300:],
                             "file": raw[:400].decode("utf-8", "backslashreplace"), "args": args})
        results.append((i, argvs[i], code, err))
    t_run = time.monotonic()
    mismatches = []
    for i, argv, code, err in rng.sample(sorted(results), min(n_subprocess, len(results))):
        c2, _, e2 = run_subprocess(argv)
        if (c2, e2) != (code, err):
            mismatches.append({"case": i, "fork": [code, err[-300:]], "subprocess": [c2, e2[-300:]]})
    if own:
        import shutil
        shutil.rmtree(workdir, ignore_errors=True)
    return {"cases": len(cases), "candidates_per_base": dict(per_base), "bases": {b[0]: baseline[b[0]] for b in bases},
            "exit_codes": dict(codes), "verdicts": dict(verdicts), "untagged_changed_detected": dict(untagged),
            "failures": failures, "subprocess_checked": min(n_subprocess, len(results)),
            "subprocess_mismatches": mismatches,
            "seconds": {"build": round(t_built - t0, 1), "fork_cases": round(t_run - t_built, 1),
                        "subprocess": round(time.monotonic() - t_run, 1)}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=23)
    ap.add_argument("--subprocess", type=int, default=0, help="also run this many cases through python -m meshmark")
    ap.add_argument("--jobs", type=int, default=2, help="children at a time")
    a = ap.parse_args(argv)
    r = campaign(a.cases, a.seed, a.subprocess, jobs=a.jobs)
    print(json.dumps(r, indent=1, ensure_ascii=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
