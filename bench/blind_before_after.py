"""Bench: blind embed, extract and issue of one source tree against another (issue 22: "blind embed
and extract no slower than before"), on the same meshes, in alternating child processes.

    .venv/bin/python bench/blind_before_after.py --before /tmp/old/src [--after src] [--repeat 3]

--before / --after: a directory holding the ``meshmark`` package with its compiled ``_core`` (e.g. an
older commit exported with ``git archive`` and built as docs/development.md describes; --after
defaults to this checkout's src). The meshes are made once here (the Bunny as shipped, 35,947
vertices, and the 100k-vertex asset of bench/informed_bench.py) and handed to both trees as .npy files.
Each child times, after one warm-up embedding: ``framework.embed`` with the product defaults
(automatic parameters, a 9-byte text), ``framework.extract`` of that copy, and ``tracing.issue`` of 10
blind copies (``informed=False`` where the tree has the option). --repeat children per tree and mesh,
run before, after, before, after, ...; best and median printed.
"""
import argparse
import inspect
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def child(npz):
    from meshmark.watermark import framework, tracing
    d = np.load(npz)
    V, F = d["V"], d["F"]
    framework.embed(V, F, payload="warm-up", key="w")
    t = time.perf_counter()
    r = framework.embed(V.copy(), F.copy(), payload="meshmark!", key="k")
    t_embed = time.perf_counter() - t
    t = time.perf_counter()
    x = framework.extract(r.V.copy(), F.copy(), keyfile=r.keyfile)
    t_extract = time.perf_counter() - t
    kw = {"informed": False} if "informed" in inspect.signature(tracing.issue).parameters else {}
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        tracing.issue(V, F, key="k", registry=os.path.join(tmp, "r.sqlite"), n_copies=10, **kw)
        t_issue = time.perf_counter() - t
    return {"embed": t_embed, "extract": t_extract, "issue10": t_issue, "detected": bool(x.detected),
            "message_ok": bool(x.message_ok)}


def meshes(tmp):
    sys.path.insert(0, HERE)
    import meshmark
    from _common import SHARED
    from informed_bench import asset

    out = []
    for name, m in (("bunny", meshmark.read_mesh(SHARED / "classic" / "bunny.obj")), ("100k", asset(100_000))):
        p = os.path.join(tmp, f"{name}.npz")
        np.savez(p, V=m.V, F=m.F)
        out.append((name, m.n_vertices, p))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", help="src directory of the older tree (meshmark package with its _core)")
    ap.add_argument("--after", default=os.path.join(os.path.dirname(HERE), "src"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--child", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        print(json.dumps(child(a.child)))
        return 0
    if not a.before:
        ap.error("--before is required")
    trees = {"before": os.path.abspath(a.before), "after": os.path.abspath(a.after)}
    with tempfile.TemporaryDirectory() as tmp:
        res = {}
        for name, n, p in meshes(tmp):
            for _ in range(a.repeat):
                for label, src in trees.items():
                    env = dict(os.environ, PYTHONPATH=src)
                    q = subprocess.run([sys.executable, __file__, "--child", p], env=env, capture_output=True,
                                       text=True, cwd=tmp)
                    if q.returncode != 0:
                        print(f"{name} {label}: failed: {q.stderr.strip().splitlines()[-1:]}", flush=True)
                        continue
                    res.setdefault((name, n, label), []).append(json.loads(q.stdout.strip().splitlines()[-1]))
    print(f"| mesh | vertices | tree | embed s best (median) | extract s best (median) | issue 10 blind s best (median) | detected |")
    print("|---|---|---|---|---|---|---|")
    for (name, n, label), rs in res.items():
        cell = lambda k: f"{min(r[k] for r in rs):.3f} ({np.median([r[k] for r in rs]):.3f})"
        print(f"| {name} | {n:,} | {label} | {cell('embed')} | {cell('extract')} | {cell('issue10')} | "
              f"{sum(r['detected'] and r['message_ok'] for r in rs)}/{len(rs)} |")
    for name, n in {(k[0], k[1]) for k in res}:
        b, f = res.get((name, n, "before")), res.get((name, n, "after"))
        if b and f:
            print(f"{name}: after / before (medians): " + ", ".join(
                f"{k} {np.median([r[k] for r in f]) / np.median([r[k] for r in b]):.2f}" for k in ("embed", "extract", "issue10")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
