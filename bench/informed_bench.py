"""Bench: issue 22's speed criteria for informed tracing, with references in the same process.

    .venv/bin/python bench/informed_bench.py [--copies 100] [--repeat 3] [--big] [--no-100k]

Every timing is run --repeat times and printed as best and median, wall and CPU (CPU of this
process: both threads of 2 count, so on a shared machine it is the figure the other jobs do not change).

1. Issuing --copies copies of a 100k-vertex asset (the Bunny after one Loop step, 143,777 vertices,
   simplified to 100,000), with the pattern (the default; --repeat runs) and without it (blind only;
   --blind-repeat runs), so the pattern's share is visible. Target: <= 20 s on 2 cores.
2. Informed traces against that registry (--copies copies), target <= 2 s: a 100k-vertex suspect whose
   vertices and order survived (noise 0.1 %: same-vertex correspondence), a 100k-vertex suspect moved,
   scaled and reordered (similarity + reorder: closest-point correspondence), and a copy simplified to
   50 % and moved (50k vertices, closest points). The first is split into factorisation, alignment
   and detection.
3. References: closest points to the surface (ours) against scipy's cKDTree nearest *vertex* query on
   the same points, with the simplified copy in the original's place (as after alignment; points far
   from the tree's data make a k-d tree query many times slower) (a lower bound: a vertex query is cheaper than a triangle query), Umeyama's fit
   against numpy's SVD of the same cross-covariance, keyed fields against numpy's default_rng normal.
4. --big: a 1.28M-vertex suspect (the elephant after three Loop steps, moved, scaled and reordered)
   traced against a registry of --copies copies of it: 4 issued for real, the others recorded with
   random codewords (the informed statistic correlates every recorded copy id's keyed field, the blind
   test every codeword, whether or not the mesh was written). Target: <= 15 s.
"""
import argparse
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import meshmark  # noqa: E402
from meshmark import _core, attacks  # noqa: E402
from meshmark.watermark import informed, tracing  # noqa: E402

from _common import SHARED, best_of, fmt, random_codeword, timings  # noqa: E402


def asset(n_target):
    """~100k: the Bunny after one Loop step (143,777 vertices) simplified to 100k; 1M: the elephant
    after three Loop steps (1.28M vertices)."""
    if n_target >= 1_000_000:
        m = meshmark.weld_vertices(meshmark.read_mesh(SHARED / "classic" / "elephant.off")).mesh
        return attacks.subdivide(m, scheme="loop", levels=3)
    m = meshmark.weld_vertices(meshmark.read_mesh(SHARED / "classic" / "bunny.obj")).mesh
    m = attacks.subdivide(m, scheme="loop")
    return attacks.simplify(m, fraction=n_target / m.n_vertices)


def issue_into(m, copies, repeat, informed_on=True):
    """Issue ``copies`` copies into a fresh registry ``repeat`` times; the timings and the last (dir, out)."""
    tmp = tempfile.mkdtemp(prefix="mm-bench-")
    k = [0]

    def run():
        k[0] += 1
        reg = os.path.join(tmp, f"r{k[0]}.sqlite")
        return reg, tracing.issue(m, key="k", registry=reg, n_copies=copies, informed=informed_on)

    w, c, (reg, out) = timings(run, repeat)
    return w, c, reg, out


def trace_case(name, sus, reg, m, cid, repeat):
    w, c, r = timings(lambda: tracing.trace(sus, registry=reg, original=m), repeat)
    inf = r["informed"] or {}
    print(f"  trace, {name} ({sus.n_vertices} vertices, {inf.get('correspondence', '?')}): {fmt(w, c)}; "
          f"copy {r['copy']} (truth {cid}), z {inf.get('z', float('nan')):.1f}", flush=True)
    return w


def bench_100k(copies, repeat, blind_repeat):
    m = asset(100_000)
    print(f"100k asset: {m.n_vertices} vertices, {m.n_faces} faces", flush=True)
    w, c, reg, out = issue_into(m, copies, repeat)
    print(f"issue {copies} copies with the pattern (default): {fmt(w, c)}  [target <= 20 s]", flush=True)
    w0, c0, _, _ = issue_into(m, copies, blind_repeat, informed_on=False)
    print(f"issue {copies} copies blind only (informed=False): {fmt(w0, c0)}; pattern share "
          f"{w['median'] - w0['median']:.1f} s of the medians", flush=True)
    cid, V = out[copies // 2]
    mc = m.with_vertices(V)
    print(f"informed trace against {copies} copies [target <= 2 s]:", flush=True)
    trace_case("noise 0.1 %", attacks.noise(mc, strength=0.001, seed=1), reg, m, cid, repeat)
    trace_case("similarity + reorder", attacks.similarity(attacks.reorder(mc, seed=1), seed=1), reg, m, cid, repeat)
    simplified = attacks.simplify(mc, fraction=0.5)
    sus = attacks.similarity(simplified, seed=1)
    trace_case("simplified 50 % + similarity", sus, reg, m, cid, repeat)
    rb, _, _ = timings(lambda: tracing.trace(sus, registry=reg), repeat)
    print(f"  of which a blind-only trace of the last: {fmt(rb)}", flush=True)
    with tracing.Registry(reg) as R:
        (_, setup, _), = R.assets()
    orig = informed.Original(m, setup["informed"])
    t_op, _, _ = timings(lambda: informed.Original(m, setup["informed"]).op, repeat)
    t_al, _, _ = timings(lambda: informed.align(sus, orig), repeat)
    seeds = [informed.copy_seed("k", tracing.source_digest(m), c) for c, _ in out]
    t_det, _, _ = timings(lambda: informed.detect(sus, orig, seeds), repeat)
    print(f"  parts (last suspect): factorisation {fmt(t_op)}; alignment {fmt(t_al)}; "
          f"detect incl. alignment {fmt(t_det)}", flush=True)
    return orig, simplified  # the references query the suspect in the original's place (as after alignment)


def references(orig, sus):
    Ts = np.ascontiguousarray(informed._tri(sus), np.int32)
    P = orig.V
    t_ours, _ = best_of(lambda: _core.closest_points(P, sus.V, Ts), 3)
    from scipy.spatial import cKDTree

    t_kd, _ = best_of(lambda: cKDTree(sus.V).query(P), 3)
    print(f"references (best of 3 / 5): closest points on the surface, {len(P)} queries on {len(Ts)} triangles: "
          f"{t_ours:.3f} s; cKDTree (build + nearest vertex) {t_kd:.3f} s: ratio {t_ours / t_kd:.2f}", flush=True)
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
    print(f"  Umeyama on 100k pairs: {t_u * 1e3:.1f} ms, numpy {t_nu * 1e3:.1f} ms: ratio {t_u / t_nu:.2f}", flush=True)
    n = len(orig.V)
    t_g, _ = best_of(lambda: _core.keyed_gaussians(list(range(16)), n), 3)
    t_ng, _ = best_of(lambda: np.random.default_rng(1).standard_normal((n, 16)), 3)
    print(f"  keyed fields, 16 x {n}: {t_g:.3f} s, numpy default_rng {t_ng:.3f} s: ratio {t_g / t_ng:.2f}", flush=True)
    u = rng.normal(size=n)
    t_d, _ = best_of(lambda: _core.keyed_gaussian_dots(u, list(range(100))), 3)
    print(f"  correlation with 100 keyed fields of {n}: {t_d:.3f} s", flush=True)


def bench_1m(copies, repeat):
    m = asset(1_000_000)
    print(f"1M asset: {m.n_vertices} vertices, {m.n_faces} faces", flush=True)
    n_real = min(4, copies)
    w, c, reg, out = issue_into(m, n_real, 1)
    print(f"  issue {n_real} copies: {fmt(w, c)}", flush=True)
    with tracing.Registry(reg) as R:
        (asset_id, _, C), = R.assets()
        R.begin()
        R.add_copies(asset_id, [(f"x{i:04d}", random_codeword(C), None) for i in range(copies - n_real)])
        R.commit()
        print(f"  registry: {R.n_copies(asset_id)} copies ({n_real} issued)", flush=True)
    cid, V = out[1]
    sus = attacks.similarity(attacks.reorder(m.with_vertices(V), seed=2), seed=2)
    print(f"informed trace against {copies} copies [target <= 15 s]:", flush=True)
    trace_case("similarity + reorder", sus, reg, m, cid, repeat)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--copies", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--blind-repeat", type=int, default=1, help="runs of the blind-only issue (default 1)")
    ap.add_argument("--big", action="store_true", help="also the 1.28M-vertex suspect")
    ap.add_argument("--no-100k", action="store_true", help="skip the 100k-vertex issue, traces and references")
    a = ap.parse_args()
    if not a.no_100k:
        references(*bench_100k(a.copies, a.repeat, a.blind_repeat))
    if a.big:
        bench_1m(a.copies, a.repeat)


if __name__ == "__main__":
    main()
