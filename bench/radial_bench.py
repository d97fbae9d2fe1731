"""Speed of the radial watermarks and of the §6.4 steganalyzer against the numpy reference.

    python bench/radial_bench.py [--min-vertices 1000000] [--repeat 3] [--ref-repeat 2] [--skip-reference-sweep]

Embed + extract of Cho's mean and variance methods and of Yang's method (the papers' own interface,
64 bits, same parameters on both sides) on the shared bunny midpoint-subdivided to >= 1M vertices, and
the steganalyzer sweep K = 1..500 on the bunny; the numpy reference (bench/reference/radial_ref.py,
sklearn's GaussianMixture for the sweep) runs in the same process, interleaved with the native runs.
Both sides report their best wall time (--repeat native runs, --ref-repeat reference runs). Prints
times, ratios and the machine's load average. Target: >= 10x for embed+extract on >= 1M vertices,
<= 1 s for the sweep.
"""
from __future__ import annotations

import argparse
import os
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE / "reference"))

import meshmark  # noqa: E402
from meshmark.steganalysis import cho as stega  # noqa: E402
from meshmark.watermark import cho, radial  # noqa: E402
import radial_ref as ref  # noqa: E402
from _common import SHARED, best_of, big_bunny  # noqa: E402


def referenced(m):
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    return np.ascontiguousarray(m.V[used])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--min-vertices", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ref-repeat", type=int, default=2)
    ap.add_argument("--skip-reference-sweep", action="store_true")
    a = ap.parse_args()
    faces = 2 * a.min_vertices
    m = big_bunny(min_faces=faces)
    V = referenced(m)
    while len(V) < a.min_vertices:
        faces *= 2
        m = big_bunny(min_faces=faces)
        V = referenced(m)
    print(f"big bunny: {len(V)} referenced vertices, {m.n_faces} faces; load average {os.getloadavg()[0]:.2f}")
    bits = np.random.default_rng(2013).integers(0, 2, 64)
    rows = []

    def row(name, f_native, f_ref):
        tn = tr = float("inf")
        for i in range(max(a.repeat, a.ref_repeat)):  # interleaved, so that load changes hit both sides
            if i < a.repeat:
                t, outn = best_of(f_native, 1)
                tn = min(tn, t)
            if i < a.ref_repeat:
                t, outr = best_of(f_ref, 1)
                tr = min(tr, t)
        ok = np.array_equal(outn, outr)
        rows.append((name, tn, tr, tr / tn, ok))
        print(f"{name:<34} native {tn:8.3f} s   reference {tr:8.3f} s   ratio {tr / tn:6.1f}x   same bits: {ok}",
              flush=True)

    for method in ("mean", "variance"):
        for ci, guard in ((0, 0.0), (5, 0.005)):
            def nat(method=method, ci=ci, guard=guard):
                Vm, _ = cho.embed_bits(V, None, bits, method=method, guard=guard, center_iters=ci)
                return cho.extract_bits(Vm, None, 64, method=method)[0]

            def rf(method=method, ci=ci, guard=guard):
                emb = ref.cho_mean_embed if method == "mean" else ref.cho_variance_embed
                ext = ref.cho_mean_extract if method == "mean" else ref.cho_variance_extract
                Vm, _ = emb(V, bits, center_iters=ci, guard=guard)
                return ext(Vm, 64)[0]
            row(f"cho-{method} embed+extract" + (f" (guard, {ci} iters)" if ci else ""), nat, rf)

    def nat_y():
        Vm, info = radial.embed_bits(V, None, bits, K=400, n_thr=None)
        return radial.extract_bits(Vm, None, 64, K=400)[0]

    def ref_y():
        Vm, info = ref.yang_radial_embed(V, bits, K=400, n_thr=radial.default_n_thr(len(V), 400))
        return ref.yang_radial_extract(Vm, 64, K=400)[0]
    row("radial (Yang) embed+extract", nat_y, ref_y)

    bunny = meshmark.read_mesh(SHARED / "classic" / "bunny.obj")
    Vb = referenced(bunny)
    Vc, _ = cho.embed_bits(Vb, None, np.tile([0, 1], 32), method="mean")
    tn, r = best_of(lambda: stega.analyze(Vc, None), a.repeat)
    print(f"steganalysis sweep K=1..500 on the marked bunny ({len(Vb)} vertices): native {tn:.3f} s "
          f"(K'={r['k_estimate']}, marked={r['marked']})", flush=True)
    if not a.skip_reference_sweep:
        t0 = time.perf_counter()
        rr = ref.cho_steganalysis(Vc)
        tr = time.perf_counter() - t0
        print(f"   reference (sklearn GMM) {tr:.2f} s (K'={rr['K_est']}, marked={rr['marked']}); ratio {tr / tn:.1f}x")
    print(f"\nload average at the end {os.getloadavg()[0]:.2f} (1 min), {os.getloadavg()[1]:.2f} (5 min)")
    print("\n| operation | native s | reference s | ratio | same bits |\n|---|---:|---:|---:|---|")
    for name, tn_, tr_, q, ok in rows:
        print(f"| {name} | {tn_:.3f} | {tr_:.3f} | {q:.1f}x | {ok} |")


if __name__ == "__main__":
    main()
