"""Sanity check of laplacian_ref.py on real meshes (thesis defaults).

Run:  cd bench/reference && ../../.venv/bin/python check_laplacian_ref.py
Unreferenced vertices are DROPPED by the loader (bunny: 35947 records -> 34834 vertices).
"""
import sys
import time
import numpy as np
from scipy.sparse.linalg import eigsh
from _load import load_mesh
import laplacian_ref as lr
import _attacks as A

MESHES = "/work/shared/meshes/classic/"
SEEDS = range(5)


def run(name):
    V, F, info = load_mesh(MESHES + name)
    N = len(V)
    K = lr.default_K(N)
    C = lr.capacity(V, F)
    diag = lr.bbox_diag(V)
    M = lr.kirchhoff(N, F)
    ev = np.sort(eigsh(M, k=3, sigma=0, which="LM", return_eigenvectors=False))
    print("\n== %s: %d vertex records, %d unreferenced dropped -> N = %d, faces %d"
          % (name, info["n_records"], info["n_unreferenced"], N, len(F)))
    print("   K = ceil(N/70) = %d, n_thr = 46, n_robust = 5 -> capacity C = %d (max floor((K-2)/2) = %d)"
          % (K, C, lr.n_pairs(K)))
    print("   eigenvalues of M = K - eps*I nearest 0: %s  (eps = 1e-5; Fiedler/eps = %.0f)"
          % (np.array2string(ev, precision=3), ev[1] / 1e-5))
    if info["n_unreferenced"]:
        V2, F2, _ = load_mesh(MESHES + name, drop_unreferenced=False)
        print("   (keeping the %d unreferenced vertices: N = %d, K = %d, capacity = %d; same K=%d: %d)"
              % (info["n_unreferenced"], len(V2), lr.default_K(len(V2)), lr.capacity(V2, F2),
                 K, lr.capacity(V2, F2, K=K)))
    rows = []
    for s in SEEDS:
        rng = np.random.default_rng(s)
        bits = rng.integers(0, 2, C)
        t = time.time()
        Xh, side = lr.embed(V, F, bits)
        te = time.time() - t
        r = dict(t=te, moved=side["n_moved"], changed=side["n_pairs_changed"])
        r["cdr_blind"] = lr.cdr(bits, lr.extract(Xh, F, n_bits=C))
        r["cdr_side"] = lr.cdr(bits, lr.extract(Xh, F, side))
        r["drift"] = np.linalg.norm(Xh.mean(0) - V.mean(0)) / diag
        r["rmse"] = np.sqrt(((Xh - V) ** 2).sum(1).mean()) / diag
        Xc = Xh - Xh.mean(0) + V.mean(0)
        r["rmse_c"] = np.sqrt(((Xc - V) ** 2).sum(1).mean()) / diag
        Xf = A.f32(Xh)
        r["f32_blind"] = lr.cdr(bits, lr.extract(Xf, F, n_bits=C))
        r["f32_side"] = lr.cdr(bits, lr.extract(Xf, F, side))
        Xn = A.noise(Xh, 1e-3, rng)
        r["n3_blind"] = lr.cdr(bits, lr.extract(Xn, F, n_bits=C))
        r["n3_side"] = lr.cdr(bits, lr.extract(Xn, F, side))
        Xn = A.noise(Xh, 1e-5, rng)
        r["n5_blind"] = lr.cdr(bits, lr.extract(Xn, F, n_bits=C))
        r["n5_side"] = lr.cdr(bits, lr.extract(Xn, F, side))
        rows.append(r)
    m = {k: np.mean([r[k] for r in rows]) for k in rows[0]}
    mn = {k: np.min([r[k] for r in rows]) for k in rows[0]}
    print("   embed time %.2f s; moved elements %.0f; pairs altered %.1f of %d" % (m["t"], m["moved"], m["changed"], C))
    print("   mean over %d random messages (min in brackets):" % len(rows))
    print("   no attack      CDR blind %.3f (%.3f)  with side info %.3f (%.3f)"
          % (m["cdr_blind"], mn["cdr_blind"], m["cdr_side"], mn["cdr_side"]))
    print("   centroid drift / bbox diag = %.3e ; RMSE / diag = %.3e ; RMSE after re-centring / diag = %.3e"
          % (m["drift"], m["rmse"], m["rmse_c"]))
    print("   float32 cast   CDR blind %.3f (%.3f)  side %.3f (%.3f)"
          % (m["f32_blind"], mn["f32_blind"], m["f32_side"], mn["f32_side"]))
    print("   noise 0.1%%    CDR blind %.3f (%.3f)  side %.3f (%.3f)"
          % (m["n3_blind"], mn["n3_blind"], m["n3_side"], mn["n3_side"]))
    print("   noise 0.001%%  CDR blind %.3f (%.3f)  side %.3f (%.3f)"
          % (m["n5_blind"], mn["n5_blind"], m["n5_side"], mn["n5_side"]))


if __name__ == "__main__":
    print("laplacian_ref check (thesis defaults: eps=1e-5, K=ceil(N/70), n_thr=46, n_robust=5)")
    print("thesis Table 7.1 Bunny: N=34835, K=498, C=21 (different bunny file, see docs/laplacian.md)")
    for name in (sys.argv[1:] or ["bunny.obj", "hand.obj", "cow.obj"]):
        run(name)
