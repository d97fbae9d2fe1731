"""Bench: attacks and the surface distance on a mesh of >= 1,000,000 triangles, each next to the same
operation in vectorized numpy/scipy or pymeshlab, in the same process. Not a test.

    .venv/bin/python bench/attacks_bench.py [--repeat 3]

Targets (attacks issue): noise, smoothing (50 iterations) and quantization no slower than vectorized
numpy/scipy; the one-sided Hausdorff/RMS distance no slower than pymeshlab's get_hausdorff_distance at
equal sample counts (all vertices + one area sample per triangle). Ratios > 1 mean meshmark is faster.
"""
import argparse
import time

import numpy as np
import scipy.sparse as sp

import meshmark
from meshmark import attacks as A, metrics as M
from _common import best_of, big_bunny


def numpy_noise(V, F, strength, seed):
    """eq. 6.3.12 in numpy: U[-A, A] d-bar per coordinate on the referenced vertices."""
    used = np.zeros(len(V), bool)
    used[F.ravel()] = True
    X = V[used]
    dbar = np.linalg.norm(X - X.mean(0), axis=1).mean()
    U = np.random.default_rng(seed).uniform(-1.0, 1.0, V.shape)
    return V + (strength * dbar) * U * used[:, None]


def scipy_smooth(V, F, lam, iterations):
    """Uniform Laplacian smoothing with a scipy CSR adjacency (the usual vectorized implementation)."""
    n = len(V)
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    e = np.unique(np.sort(e, 1), axis=0)
    Adj = sp.csr_matrix((np.ones(2 * len(e)), (np.r_[e[:, 0], e[:, 1]], np.r_[e[:, 1], e[:, 0]])), shape=(n, n))
    deg = np.asarray(Adj.sum(1)).ravel()
    inv = np.divide(1.0, deg, out=np.zeros(n), where=deg > 0)[:, None]
    move = (deg > 0)[:, None]
    X = V.copy()
    for _ in range(iterations):
        X = X + lam * move * ((Adj @ X) * inv - X)
    return X


def numpy_quantize(V, bits):
    lo, hi = V.min(0), V.max(0)
    step = (hi - lo) / 2.0 ** bits
    u = (V - lo) / step
    k = np.floor(u)
    k += (u - k) > 0.5
    return lo + k * step


def pymeshlab_set(a, b):
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(a.V, a.F))
    ms.add_mesh(pymeshlab.Mesh(b.V, b.F))
    return ms


def pymeshlab_distance(ms, n, maxdist):
    import pymeshlab
    return ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, samplevert=True, sampleface=True,
                                     sampleedge=False, samplefauxedge=False, samplenum=int(n),
                                     maxdist=pymeshlab.PureValue(maxdist))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    mesh = big_bunny()
    used = np.zeros(mesh.n_vertices, bool)
    used[mesh.face_indices] = True
    mesh = meshmark.Mesh(mesh.V[used], (np.cumsum(used) - 1)[mesh.F])   # compact: pymeshlab samples every vertex
    V, F = mesh.V, mesh.F
    print(f"mesh: bunny midpoint-subdivided, {mesh.n_vertices:,} vertices, {mesh.n_faces:,} triangles")
    rows = []

    t_mm, out = best_of(lambda: A.noise(mesh, strength=0.0025, seed=0), args.repeat)
    t_np, ref = best_of(lambda: numpy_noise(V, F, 0.0025, 0), args.repeat)
    d = A.mean_centroid_distance(mesh) * 0.0025
    assert np.abs(out.V - V).max() <= d * (1 + 1e-12) and np.abs(ref - V).max() <= d * (1 + 1e-12)
    rows.append(("uniform noise A = 0.25 %", t_mm, "numpy", t_np))

    t_mm, out = best_of(lambda: A.smooth(mesh, lam=0.02, iterations=50), max(1, args.repeat - 1))
    t_np, ref = best_of(lambda: scipy_smooth(V, F, 0.02, 50), max(1, args.repeat - 1))
    err = np.abs(out.V - ref).max()
    assert err < 1e-12 * M.bbox_diagonal(mesh), err
    rows.append(("Laplacian smoothing 50 its", t_mm, "scipy.sparse", t_np))

    t_mm, out = best_of(lambda: A.quantize(mesh, bits=10), args.repeat)
    t_np, ref = best_of(lambda: numpy_quantize(V, 10), args.repeat)
    assert np.array_equal(out.V, ref)
    rows.append(("quantization 10 bits", t_mm, "numpy", t_np))

    noisy = A.noise(mesh, strength=0.0025, seed=1)
    n = mesh.n_faces
    t0 = time.perf_counter()
    ours = M.one_sided_distance(mesh, noisy, n_samples=n, seed=0)
    t_mm = time.perf_counter() - t0
    ms = pymeshlab_set(mesh, noisy)
    t0 = time.perf_counter()
    pml = pymeshlab_distance(ms, n, 4 * M.bbox_diagonal(mesh))
    t_pml = time.perf_counter() - t0
    assert ours["n_samples"] == pml["n_samples"]
    rows.append((f"distance A->B, {ours['n_samples']:,} samples", t_mm, "pymeshlab", t_pml))
    print(f"  (Hausdorff ours {ours['max']:.6e} pymeshlab {pml['max']:.6e}; RMS ours {ours['rms']:.6e} "
          f"pymeshlab {pml['RMS']:.6e}; pymeshlab time excludes building its MeshSet)")

    print(f"{'operation':<38}{'meshmark (s)':>13}{'reference':>15}{'ref (s)':>10}{'speed-up':>10}")
    for name, a, ref_name, b in rows:
        print(f"{name:<38}{a:>13.3f}{ref_name:>15}{b:>10.3f}{b / a:>9.2f}x")


if __name__ == "__main__":
    main()
