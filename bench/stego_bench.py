"""Bench: meshmark.stego embed + extract on a >= 1M-vertex mesh (the Elephant, midpoint-subdivided).

    .venv/bin/python bench/stego_bench.py [--adaptive triangle|global] [--precision fixed32]

Runs in a child process so that the peak RSS (ru_maxrss) is the stego run's own. Prints the wall times
of embed and extract (best of 2 each), the share of the quantization levels (meshmark.analysis, called
twice by embed and once by extract) and of the scrypt key stretching, and, as the in-process
reference, the ratio of the native pi ordering (exact-sum PCA + sort) to numpy doing the same
(float PCA + np.lexsort). Target (issue 13): embed + extract <= 2 s, RSS <= 1 GB.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def load():
    import meshmark
    from _common import SHARED, midpoint_subdivide
    m = meshmark.read_mesh(SHARED / "classic" / "elephant.off")
    V, F = m.V, m.F
    while len(V) < 1_000_000:
        V, F = midpoint_subdivide(V, F)
    return meshmark.Mesh(V, F)


def child(adaptive, precision):
    import meshmark
    from meshmark import _core, stego
    from meshmark.stego import crypto, lsb

    m = load()
    payload = os.urandom(1 << 20)  # 1 MiB
    ad = {"triangle": True, "global": False}[adaptive]
    level_fn = lsb.level_function(1.0, ad)
    t = time.process_time()
    level_fn(m)
    t_level = time.process_time() - t  # CPU seconds (the machine is shared)
    t = time.process_time()
    crypto.derive(b"k", b"0" * 16)
    t_kdf = time.process_time() - t
    te, tx, ce, cx = [], [], [], []
    for _ in range(2):
        mm = meshmark.Mesh.from_polygons(m.V.copy(), m.face_indices.copy(), m.face_offsets.copy())
        t, c = time.perf_counter(), time.process_time()
        r = stego.embed(mm, payload, "bench key", tolerance=1.0, adaptive=ad, precision=precision)
        te.append(time.perf_counter() - t)
        ce.append(time.process_time() - c)
        marked = meshmark.Mesh.from_polygons(r.V.copy(), m.face_indices.copy(), m.face_offsets.copy())
        t, c = time.perf_counter(), time.process_time()
        x = stego.extract(marked, "bench key", tolerance=1.0, adaptive=ad, precision=precision)
        tx.append(time.perf_counter() - t)
        cx.append(time.process_time() - c)
        assert x.found and x.message == payload
    # in-process reference: the pi ordering, native vs numpy
    E, o = _core.stego_frame(m.V, precision)
    C = _core.stego_snap(m.V, precision, E, o)
    tt = r.t
    Q = _core.stego_quantize(C, tt, precision, E, o)
    t = time.process_time()
    _core.stego_order(Q, tt, E, o, m.face_indices, m.face_offsets)
    t_native = time.process_time() - t
    t = time.process_time()
    c = Q.mean(0)
    w, U = np.linalg.eigh(np.cov((Q - c).T))
    p = (Q - c) @ U[:, -1]
    np.lexsort((tt, Q[:, 2], Q[:, 1], Q[:, 0], p))
    t_numpy = time.process_time() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"n": m.n_vertices, "faces": m.n_faces, "embed": min(te), "extract": min(tx), "embed_cpu": min(ce), "extract_cpu": min(cx),
                      "level_call": t_level, "kdf": t_kdf, "order_native": t_native, "order_numpy": t_numpy,
                      "rss_mb": peak, "bpv": r.bits_per_vertex}))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--adaptive", default="triangle", choices=["triangle", "global"])
    ap.add_argument("--precision", default="fixed32")
    ap.add_argument("--child", action="store_true")
    a = ap.parse_args()
    if a.child:
        child(a.adaptive, a.precision)
        return
    out = subprocess.run([sys.executable, __file__, "--child", "--adaptive", a.adaptive, "--precision", a.precision],
                         capture_output=True, text=True, check=True).stdout
    d = json.loads(out.strip().splitlines()[-1])
    total = d["embed"] + d["extract"]
    print(f"{d['n']} vertices, {d['faces']} faces, levels {a.adaptive}, {a.precision}, 1 MiB payload, "
          f"{d['bpv']:.2f} bits/vertex; load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"embed {d['embed']:.2f} s + extract {d['extract']:.2f} s = {total:.2f} s "
          f"(target <= 2 s: {'met' if total <= 2 else 'NOT met'}); peak RSS {d['rss_mb']:.0f} MB "
          f"(target <= 1024 MB: {'met' if d['rss_mb'] <= 1024 else 'NOT met'})")
    cpu = d["embed_cpu"] + d["extract_cpu"]
    print(f"CPU time (one thread; the wall time above depends on the load): embed {d['embed_cpu']:.2f} s + "
          f"extract {d['extract_cpu']:.2f} s = {cpu:.2f} s (target <= 2 s: {'met' if cpu <= 2 else 'NOT met'})")
    lv = 3 * d["level_call"]
    print(f"of which quantization levels (meshmark.analysis, 3 calls): {lv:.2f} CPU-s ({100 * lv / cpu:.0f} %), "
          f"scrypt (2 derivations): {2 * d['kdf']:.2f} CPU-s; meshmark.stego's own work {cpu - lv - 2 * d['kdf']:.2f} CPU-s")
    print(f"pi ordering: native {d['order_native'] * 1e3:.0f} ms vs numpy (float PCA + lexsort, not "
          f"permutation-exact) {d['order_numpy'] * 1e3:.0f} ms: ratio {d['order_numpy'] / d['order_native']:.1f}x")


if __name__ == "__main__":
    main()
