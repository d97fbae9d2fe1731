"""Chao et al. 2009 baseline (n_layers = 10, n_intervals = 10000, thesis §8.2) beside §4.3.2.

For every shared classic mesh: Chao's capacity (bits per vertex), RMSE (relative to the bounding-box
diagonal too), mean normal degradation, the blind-extraction bit error rate of layer 1 and 10; then on
the Bunny ours at 1 deg and ours at the largest tolerance whose measured degradation does not exceed
Chao's (the thesis' claim: >= 10 more bits per vertex at no more normal degradation).

    .venv/bin/python bench/stego_chao_compare.py
"""
import pathlib

import numpy as np

import meshmark
from meshmark import stego
from meshmark.stego import chao

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes" / "classic"


def rmse(A, B):
    return float(np.sqrt(np.mean(np.sum((A - B) ** 2, axis=1))))


def main():
    print(f"{'mesh':<10} {'n':>6} {'bpv':>6} {'RMSE':>10} {'RMSE/diag':>10} {'deg':>7} {'blind BER L1':>12} {'L10':>6}")
    rows = {}
    for p in sorted(x for x in SHARED.iterdir() if x.suffix in (".obj", ".off", ".ply")):
        m = meshmark.read_mesh(p)
        r = chao.embed(m, message=b"", fill=True, seed=1)
        bits = np.random.default_rng(1).integers(0, 2, r.capacity_bits)
        assert np.array_equal(chao.extract(m.with_vertices(r.V), r.capacity_bits, frame=r.frame), bits)
        blind = (chao.extract(m.with_vertices(r.V), r.capacity_bits) != bits).reshape(-1, 3, 10).mean(axis=(0, 1))
        diag = float(np.linalg.norm(m.V.max(0) - m.V.min(0)))
        deg = meshmark.metrics.normal_degradation(m, r.V, degrees=True)
        rows[p.stem] = (r.bits_per_vertex, deg)
        print(f"{p.stem:<10} {m.n_vertices:>6} {r.bits_per_vertex:>6.2f} {rmse(m.V, r.V):>10.3e} "
              f"{rmse(m.V, r.V) / diag:>10.2e} {deg:>7.3f} {blind[0]:>12.4f} {blind[-1]:>6.3f}")
    m = meshmark.read_mesh(SHARED / "bunny.obj")
    c_bpv, c_deg = rows["bunny"]
    print(f"\nBunny: Chao {c_bpv:.2f} bits/vertex at {c_deg:.3f} deg")
    tol = 1.0
    while True:
        res = {p: stego.embed(m, b"m", "k", tolerance=tol, precision=p) for p in ("fixed32", "float64")}
        deg = meshmark.metrics.normal_degradation(m, res["fixed32"].V, degrees=True)
        print(f"ours tolerance {tol:.2f} deg: fixed32 {res['fixed32'].bits_per_vertex:.2f} bits/vertex "
              f"(+{res['fixed32'].bits_per_vertex - c_bpv:.2f} over Chao), float64 {res['float64'].bits_per_vertex:.2f}, "
              f"RMSE {rmse(m.V, res['fixed32'].V):.3e}, degradation {deg:.3f} deg "
              f"({'<=' if deg <= c_deg else '>'} Chao's)")
        if deg <= c_deg or tol < 0.05:
            break
        tol = round(tol * 0.8, 3)


if __name__ == "__main__":
    main()
