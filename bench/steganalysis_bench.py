"""Speed of the steganalysis features and of the 30-split training (issue 15 targets: 10k vertices
YANG208 <= 20 ms, LFS76 <= 40 ms; 30 splits over the shared corpus <= 10 min; thesis: 6 s per model).

    .venv/bin/python bench/steganalysis_bench.py [--dataset out/steganalysis_dataset.npz]

Features: best of 10 on corpus/vhacd_foot.off (10,010 vertices), against the vectorised numpy/scipy
reference of YANG208 (bench/reference/yang208_ref.py) in the same process. Training: the protocol of
examples/steganalysis_protocol.py (one feature set x classifier, every detector, 30 splits) on a
cached dataset, if given.
"""
from __future__ import annotations

import argparse
import pathlib
import sys
import time

import numpy as np

import meshmark
from meshmark import _core

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "reference"))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import SHARED, best_of  # noqa: E402
import yang208_ref  # noqa: E402


def best_cpu(fn, repeat=10):
    """Best CPU time of the calling thread (s): less sensitive than wall time to the other jobs on a
    shared machine (the native code runs on one thread)."""
    best = float("inf")
    for _ in range(repeat):
        t = time.thread_time()
        fn()
        best = min(best, time.thread_time() - t)
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dataset", default=None)
    ap.add_argument("--splits", type=int, default=30)
    a = ap.parse_args()
    m = meshmark.read_mesh(SHARED / "corpus" / "vhacd_foot.off")
    V, T = m.V, np.ascontiguousarray(m.triangles)
    print(f"mesh: vhacd_foot.off, {m.n_vertices} vertices, {len(T)} triangles")
    t_ref, Fr = best_of(lambda: yang208_ref.yang208(V, T, _core.unit_cube_normalize(V, m.referenced())), 3)
    rows = []
    for name, fn, target in [("yang208", lambda: _core.yang208_features(V, T), 0.020),
                             ("lfs76", lambda: _core.lfs76_features(V, T), 0.040),
                             ("nvt36", lambda: _core.nvt36_features(V, T), None)]:
        t, F = best_of(fn, 10)
        rows.append((name, t, target, best_cpu(fn)))
        if name == "yang208":
            err = np.max(np.abs(F - Fr) / (1 + np.abs(Fr)))
            print(f"yang208 native vs numpy reference: max relative difference {err:.1e}")
    import os
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print("| set | native wall | native CPU | target | thesis (6 s) ratio | numpy reference ratio (wall) |\n|---|---:|---:|---:|---:|---:|")
    for name, t, target, cpu in rows:
        print(f"| {name} | {t * 1e3:.1f} ms | {cpu * 1e3:.1f} ms | {'%.0f ms' % (target * 1e3) if target else '-'} | {6.0 / t:.0f}x | "
              + (f"{t_ref / t:.1f}x ({t_ref * 1e3:.0f} ms) |" if name == "yang208" else "- |"))
    if a.dataset:
        from meshmark.steganalysis import protocol as P
        ds = P.load_dataset(a.dataset)
        for fs, c in [("yang208", "qda"), ("yang208", "ensemble"), ("lfs76+nvt36", "ensemble")]:
            t = time.perf_counter()
            P.evaluate(ds, fs, c, a.splits)
            n_det = len({x for x in ds["method"] if x != "cover"}) + 1
            print(f"training+testing {fs} + {c}: {n_det} detectors x {a.splits} splits on {len(ds['method'])} "
                  f"meshes: {time.perf_counter() - t:.1f} s (target 600 s)")


if __name__ == "__main__":
    main()
