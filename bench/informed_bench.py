"""Bench: informed tracing's costs, with references in the same process.

    .venv/bin/python bench/informed_bench.py [--big] [--copies 100]

1. Issuing --copies copies of a ~100k-vertex asset (the Bunny after one Loop step, simplified to 100k
   vertices), with the pattern and without (today's blind-only issue),
   so the pattern's share is visible (target: the whole issue <= 20 s on 2 cores).
2. An informed trace of a copy (simplified to 50 %, so the closest-point path runs) against the
   registry (target <= 2 s), split into alignment, resampling, filtering and correlation.
3. References: closest points to the surface (ours) against scipy's cKDTree nearest *vertex* query on
   the same points (a lower bound: a vertex query is cheaper than a triangle query), Umeyama's fit
   against numpy's SVD of the same cross-covariance, keyed fields against numpy's default_rng normal.
4. --big: a 1.28M-vertex suspect (three Loop steps of the elephant) traced against its registry
   (target <= 15 s; 4 copies issued: the trace cost depends on the copies only through the
   correlation, measured separately at 100 seeds).
"""
import argparse
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import meshmark  # noqa: E402
from meshmark import _core, attacks  # noqa: E402
from meshmark.watermark import informed, tracing  # noqa: E402

from _common import SHARED, best_of  # noqa: E402


CPU = {}


def timed(fn):
    """(result, wall seconds); the CPU seconds of this process go to CPU['last'] (on a shared machine
    the CPU time is the figure the other jobs do not change; with 2 threads it bounds 2 x the wall time
    of an idle 2-core machine)."""
    t, c = time.perf_counter(), time.process_time()
    out = fn()
    CPU["last"] = time.process_time() - c
    return out, time.perf_counter() - t


def asset(n_target):
    """~100k: the Bunny after one Loop step (143,777 vertices) simplified to 100k; 1M: the elephant
    after three Loop steps (1.28M vertices)."""
    if n_target >= 1_000_000:
        m = meshmark.weld_vertices(meshmark.read_mesh(SHARED / "classic" / "elephant.off")).mesh
        return attacks.subdivide(m, scheme="loop", levels=3)
    m = meshmark.weld_vertices(meshmark.read_mesh(SHARED / "classic" / "bunny.obj")).mesh
    m = attacks.subdivide(m, scheme="loop")
    return attacks.simplify(m, fraction=n_target / m.n_vertices)


def bench_issue_trace(m, copies):
    print(f"asset: {m.n_vertices} vertices, {m.n_faces} faces", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        reg = os.path.join(tmp, "r.sqlite")
        out, t_all = timed(lambda: tracing.issue(m, key="k", registry=reg, n_copies=copies))
        c_all = CPU["last"]
        reg0 = os.path.join(tmp, "r0.sqlite")
        _, t_blind = timed(lambda: tracing.issue(m, key="k", registry=reg0, n_copies=copies, informed=False))
        print(f"issue {copies} copies: {t_all:.1f} s wall ({c_all:.1f} s CPU) with the pattern, {t_blind:.1f} s wall "
              f"({CPU['last']:.1f} s CPU) blind only "
              f"(pattern share {t_all - t_blind:.1f} s)", flush=True)
        cid, V = out[copies // 2]
        sus = attacks.simplify(m.with_vertices(V), fraction=0.5)
        sus = attacks.similarity(sus, seed=1)
        r, t_trace = timed(lambda: tracing.trace(sus, registry=reg, original=m))
        print(f"trace (simplified 50 %, {sus.n_vertices} vertices): {t_trace:.2f} s wall ({CPU['last']:.2f} s CPU), copy {r['copy']} "
              f"(truth {cid}), z {r['informed']['z']:.1f}", flush=True)
        rb, t_blind_trace = timed(lambda: tracing.trace(sus, registry=reg))
        print(f"  of which blind-only trace: {t_blind_trace:.2f} s wall ({CPU['last']:.2f} s CPU)", flush=True)
        with tracing.Registry(reg) as R:
            (_, setup, _), = R.assets()
        orig = informed.Original(m, setup["informed"])
        _, t_op = timed(lambda: orig.op)
        al, t_al = timed(lambda: informed.align(sus, orig))
        seeds = [informed.copy_seed("k", tracing.source_digest(m), c) for c, _ in out]
        det, t_det = timed(lambda: informed.detect(sus, orig, seeds))
        print(f"  parts: factorisation {t_op:.2f} s, alignment {t_al:.2f} s, detect incl. alignment {t_det:.2f} s",
              flush=True)
        return orig, sus


def references(orig, sus):
    Ts = np.ascontiguousarray(informed._tri(sus), np.int32)
    P = orig.V
    t_ours, _ = best_of(lambda: _core.closest_points(P, sus.V, Ts), 3)
    from scipy.spatial import cKDTree

    t_kd, _ = best_of(lambda: cKDTree(sus.V).query(P), 3)
    print(f"closest points on the surface, {len(P)} queries on {len(Ts)} triangles: {t_ours:.3f} s; cKDTree "
          f"(build + nearest vertex) {t_kd:.3f} s: ratio {t_ours / t_kd:.2f}", flush=True)
    rng = np.random.default_rng(0)
    A = rng.normal(size=(100000, 3))
    B = A @ attacks.random_rotation(3).T * 1.3 + 2

    def np_umeyama():
        ma, mb = A.mean(0), B.mean(0)
        S = (B - mb).T @ (A - ma) / len(A)
        U, s, Vt = np.linalg.svd(S)
        return U @ Vt

    t_u, _ = best_of(lambda: _core.umeyama(A, B, True), 5)
    t_nu, _ = best_of(np_umeyama, 5)
    print(f"Umeyama on 100k pairs: {t_u * 1e3:.1f} ms, numpy {t_nu * 1e3:.1f} ms: ratio {t_u / t_nu:.2f}", flush=True)
    n = len(orig.V)
    t_g, _ = best_of(lambda: _core.keyed_gaussians(list(range(16)), n), 3)
    t_ng, _ = best_of(lambda: np.random.default_rng(1).standard_normal((n, 16)), 3)
    print(f"keyed fields, 16 x {n}: {t_g:.3f} s, numpy default_rng {t_ng:.3f} s: ratio {t_g / t_ng:.2f}", flush=True)
    u = rng.normal(size=n)
    t_d, _ = best_of(lambda: _core.keyed_gaussian_dots(u, list(range(100))), 3)
    print(f"correlation with 100 keyed fields of {n}: {t_d:.3f} s", flush=True)


def big():
    m = asset(1_000_000)
    print(f"1M case: asset {m.n_vertices} vertices", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        reg = os.path.join(tmp, "r.sqlite")
        out, t_issue = timed(lambda: tracing.issue(m, key="k", registry=reg, n_copies=4))
        print(f"  issue 4 copies: {t_issue:.1f} s wall ({CPU['last']:.1f} s CPU)", flush=True)
        cid, V = out[1]
        sus = attacks.similarity(attacks.reorder(m.with_vertices(V), seed=2), seed=2)
        r, t = timed(lambda: tracing.trace(sus, registry=reg, original=m))
        print(f"  trace of a {sus.n_vertices}-vertex suspect: {t:.1f} s wall ({CPU['last']:.1f} s CPU), copy {r['copy']} (truth {cid}), "
              f"z {r['informed']['z']:.1f}", flush=True)
        u = np.random.default_rng(0).normal(size=m.n_vertices)
        t_d, _ = best_of(lambda: _core.keyed_gaussian_dots(u, list(range(96))), 1)
        print(f"  correlation with 96 more fields: {t_d:.1f} s (so 100 copies: trace + this)", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--copies", type=int, default=100)
    ap.add_argument("--big", action="store_true")
    a = ap.parse_args()
    orig, sus = bench_issue_trace(asset(100_000), a.copies)
    references(orig, sus)
    if a.big:
        big()


if __name__ == "__main__":
    main()
