#!/usr/bin/env python
"""Exercise attacks_ref.py / metrics_ref.py and compare the surface distance with
pymeshlab's get_hausdorff_distance.

    .venv/bin/python bench/reference/check_attacks_metrics_ref.py [--quick]

Part 1: self-checks (exact point-mesh distance vs brute force; identical-sample
        agreement with pymeshlab; invariances; thesis ch. 3/4 sanity numbers).
Part 2: table of every attack on classic/bunny.obj with RMSE, Hausdorff, MRMS and
        the three normal degradations.
Part 3: ours vs pymeshlab (Metro-derived) under uniform noise A = 0.25 % and 50 %
        quadric simplification on bunny, horse and elephant.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import _meshio_ref as mio  # noqa: E402
import attacks_ref as A  # noqa: E402
import metrics_ref as M  # noqa: E402

MESHES = os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "meshes", "classic"))


def load(name):
    V, F = mio.load_mesh(os.path.join(MESHES, name))
    V2, F2, _ = A.remove_unreferenced(V, F)
    return V2, F2, len(V) - len(V2)


def fmt(x, spec=".3e"):
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    return format(x, spec)


# --------------------------------------------------------------------------------------
def part1_selfchecks():
    print("\n== Part 1: self-checks ==")
    ok = True
    V, F, _ = load("cow.obj")
    rng = np.random.default_rng(1)
    d = M.bbox_diagonal(V)
    P = np.concatenate([V[rng.integers(0, len(V), 1500)] + rng.normal(0, 0.01 * d, (1500, 3)),
                        rng.uniform(V.min(0) - 0.2 * d, V.max(0) + 0.2 * d, (300, 3))])
    d1, _ = M.point_mesh_distance(P, V, F)
    d2, _ = M.point_mesh_distance_bruteforce(P, V, F)
    e = float(np.abs(d1 - d2).max())
    print(f"kd-tree exact distance vs brute force (cow, 1800 pts): max |diff| = {e:.2e}")
    ok &= e < 1e-12

    # same samples as pymeshlab -> distances must agree to rounding
    Vn = A.uniform_noise(V, 0.0025, seed=0)
    r = M.pymeshlab_hausdorff(V, F, Vn, F, samplenum=20000, savesample=True)
    dd, _ = M.point_mesh_distance(r["samples"], Vn, F)
    e = float(np.abs(dd - r["dist"]).max())
    print(f"ours vs pymeshlab on pymeshlab's own {len(dd)} samples: max |diff| = {e:.2e} "
          f"(max {dd.max():.6e} vs {r['max']:.6e})")
    ok &= e < 1e-9 * d

    # invariances
    Vr, R, s, t = A.random_similarity(V, seed=3)
    Vp, Fp, perm, fperm = A.permute(V, F, seed=4, rotate_corners=True)
    sd = M.surface_distance(V, F, Vp, Fp, n_samples=5000)
    print(f"permutation: surface distance {sd['hausdorff']:.1e} (expect 0)")
    ok &= sd["hausdorff"] < 1e-12
    back = (Vr - t) @ R / s
    print(f"similarity round trip max err {np.abs(back - V).max():.1e}")
    ok &= np.abs(back - V).max() < 1e-9 * d

    # detection metrics
    w = np.random.default_rng(0).integers(0, 2, 64)
    w2 = w.copy()
    w2[:6] ^= 1
    nc, ber = M.normalized_correlation(w, w2), M.bit_error_rate(w, w2)
    print(f"64 bits, 6 flipped: C={M.correlation(w, w2):.4f} NC={nc:.4f} BER={ber:.4f} "
          f"CDR={M.cdr(w, w2):.4f} Pfa(X>=58)={M.false_alarm_probability(64, 58):.3e}")
    ok &= abs(nc - (1 - 2 * ber)) < 1e-15

    # thesis sanity: ch.3 (float64 words) and ch.4 (fixed32 words) on the bunny
    Vb, Fb, _ = load("bunny.obj")
    line = []
    for t_ in (12, 20, 24):
        with np.errstate(all="ignore"):
            Vd = A.dithered_quantize(Vb, t_, seed=0, mode="float64")
        line.append(f"t={t_}: {np.degrees(M.normal_degradation(Vb, Fb, Vd)):.3f} deg")
    print("ch.3 float64 dithering, bunny dis^av: " + ", ".join(line)
          + "   (thesis Table 3.2: 1 deg at t=24, logistic C~pi/2 at t<=12)")
    line = []
    for t_ in (9, 13, 16):
        Vd = A.dithered_quantize(Vb, t_, seed=0, mode="fixed32")
        line.append(f"i={t_}: {np.degrees(M.normal_degradation(Vb, Fb, Vd)):.3f} deg")
    print("ch.4 fixed32 dithering, bunny psi^i: " + ", ".join(line)
          + "   (thesis Table 4.2 E_appr: 10/1/0.1 deg -> i = 9/13/16)")
    print("self-checks:", "PASS" if ok else "FAIL")
    return ok


# --------------------------------------------------------------------------------------
def part2_table(n_samples):
    print("\n== Part 2: attacks on classic/bunny.obj ==")
    V, F, nunref = load("bunny.obj")
    print(f"bunny: {len(V)} vertices ({nunref} unreferenced removed), {len(F)} faces, "
          f"d_bar={A.mean_centroid_distance(V):.5f}, bbox diag={M.bbox_diagonal(V):.5f}")
    diag = M.bbox_diagonal(V)
    rows = []

    def add(name, fn):
        t0 = time.time()
        out = fn()
        ta = time.time() - t0
        V2, F2 = out[0], out[1]
        same_conn = F2 is F or (F2.shape == F.shape and np.array_equal(F2, F))
        rm = M.vertex_rmse(V, V2) / diag if (len(V2) == len(V) and same_conn) else None
        if same_conn:
            with np.errstate(all="ignore"):
                nd = [np.degrees(M.normal_degradation(V, F, V2, w))
                      for w in ("mean", "area", "dihedral")]
        else:
            nd = [None] * 3
        if np.all(np.isfinite(V2)):
            sd = M.surface_distance(V, F, V2, F2, n_samples=n_samples)
            h, r = sd["hausdorff_rel"], sd["mrms_rel"]
        else:
            h = r = None
        rows.append((name, len(V2), len(F2), rm, h, r, *nd, ta))
        print(f"  done: {name}", file=sys.stderr, flush=True)

    p = A.permute(V, F, seed=1)
    inv = np.argsort(p[2])
    add("rotate (1,2,3) 30deg, unaligned", lambda: (A.rotate(V, (1, 2, 3), 30), F))
    add("rand. similarity, unaligned", lambda: (A.random_similarity(V, seed=0)[0], F))
    add("permute v+f (undone for RMSE)", lambda: (p[0][inv], F))
    for a in (0.0005, 0.0010, 0.0025, 0.0030, 0.0050):
        add(f"uniform noise A={a * 100:.2f}%", lambda a=a: (A.uniform_noise(V, a, seed=0), F))
    add("gaussian noise A=0.25%", lambda: (A.gaussian_noise(V, 0.0025, seed=0), F))
    add("normal noise A=0.25%", lambda: (A.normal_noise(V, F, 0.0025, seed=0), F))
    add("tangent noise A=0.25%", lambda: (A.tangent_noise(V, F, 0.0025, seed=0), F))
    for it in (5, 10, 30, 50):
        add(f"laplacian lam=0.02 it={it}", lambda it=it: (A.laplacian_smooth(V, F, 0.02, it), F))
    for it in (10, 50):
        add(f"cotangent lam=0.02 it={it}", lambda it=it: (A.cotangent_smooth(V, F, 0.02, it), F))
    for b in range(7, 13):
        add(f"quantize {b} bits (MEPP)", lambda b=b: (A.quantize(V, b), F))
    for t_ in (12, 16, 20):
        add(f"dither fixed32 t={t_}", lambda t_=t_: (A.dithered_quantize(V, t_, 0, "fixed32"), F))
    for t_ in (20, 24, 32):
        add(f"dither float64 t={t_}", lambda t_=t_: (A.dithered_quantize(V, t_, 0, "float64"), F))
    add("float32 cast", lambda: (A.float32_cast(V), F))
    add("midpoint subdivision x1", lambda: A.midpoint_subdivide(V, F))
    add("loop subdivision x1", lambda: A.loop_subdivide(V, F))
    for fr in (0.1, 0.3):
        add(f"crop {fr * 100:.0f}% along +y", lambda fr=fr: A.crop_plane(V, F, fr, (0, 1, 0))[:2])
    for fr in (0.9, 0.7, 0.5, 0.25):
        add(f"QEM simplify to {fr * 100:.0f}% faces", lambda fr=fr: A.simplify_qem(V, F, fr))

    hdr = (f"{'attack':32s} {'#V':>7s} {'#F':>7s} {'RMSE/diag':>10s} {'Haus/diag':>10s} "
           f"{'MRMS/diag':>10s} {'dis_av':>8s} {'dis_ar':>8s} {'dis_an':>8s} {'t[s]':>6s}")
    print(f"(surface distance: all vertices + {n_samples} area samples per direction; "
          "dis_* in degrees)")
    print(hdr)
    print("-" * len(hdr))
    for r in rows:
        print(f"{r[0]:32s} {r[1]:7d} {r[2]:7d} {fmt(r[3]):>10s} {fmt(r[4]):>10s} {fmt(r[5]):>10s} "
              f"{fmt(r[6], '.4f'):>8s} {fmt(r[7], '.4f'):>8s} {fmt(r[8], '.4f'):>8s} {r[9]:6.2f}")


# --------------------------------------------------------------------------------------
def part3_pymeshlab(factor):
    print("\n== Part 3: ours vs pymeshlab get_hausdorff_distance ==")
    print(f"both: all vertices of the sampled mesh + {factor} x #faces area-uniform samples, "
          "no maxdist rejection; sym = max of the two directions")
    hdr = (f"{'mesh':9s} {'attack':13s} {'dir':4s} {'max ours':>11s} {'max pml':>11s} {'rel.d':>8s} "
           f"{'RMS ours':>11s} {'RMS pml':>11s} {'rel.d':>8s} {'n ours':>8s} {'n pml':>8s}")
    print(hdr)
    print("-" * len(hdr))
    worst = [0.0, 0.0]
    for name in ("bunny.obj", "horse.ply", "elephant.off"):
        V, F, _ = load(name)
        attacked = {
            "noise 0.25%": (A.uniform_noise(V, 0.0025, seed=0), F),
            "QEM 50%": A.simplify_qem(V, F, 0.5),
        }
        for an, (V2, F2) in attacked.items():
            sym = {}
            for d, (Va, Fa, Vb, Fb) in (("A>B", (V, F, V2, F2)), ("B>A", (V2, F2, V, F))):
                n = factor * len(Fa)
                ours = M.one_sided_distance(Va, Fa, Vb, Fb, n_samples=n, seed=7)
                pml = M.pymeshlab_hausdorff(Va, Fa, Vb, Fb, samplenum=max(n, len(Va)))
                sym.setdefault("o", []).append((ours["max"], ours["rms"]))
                sym.setdefault("p", []).append((pml["max"], pml["RMS"]))
                rmax = ours["max"] / pml["max"] - 1
                rrms = ours["rms"] / pml["RMS"] - 1
                print(f"{name[:-4]:9s} {an:13s} {d:4s} {ours['max']:11.5e} {pml['max']:11.5e} "
                      f"{rmax:+8.2%} {ours['rms']:11.5e} {pml['RMS']:11.5e} {rrms:+8.2%} "
                      f"{ours['n']:8d} {pml['n_samples']:8d}")
            om = max(x[0] for x in sym["o"]), max(x[1] for x in sym["o"])
            pm = max(x[0] for x in sym["p"]), max(x[1] for x in sym["p"])
            rh, rr = om[0] / pm[0] - 1, om[1] / pm[1] - 1
            worst = [max(worst[0], abs(rh)), max(worst[1], abs(rr))]
            print(f"{name[:-4]:9s} {an:13s} sym  {om[0]:11.5e} {pm[0]:11.5e} {rh:+8.2%} "
                  f"{om[1]:11.5e} {pm[1]:11.5e} {rr:+8.2%}")
    print(f"worst |relative difference| (symmetric): Hausdorff {worst[0]:.2%}, MRMS {worst[1]:.2%}")
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer samples (faster, noisier)")
    ap.add_argument("--skip", default="", help="comma list of parts to skip: 1,2,3")
    a = ap.parse_args()
    skip = set(a.skip.split(",")) if a.skip else set()
    np.set_printoptions(precision=4)
    t0 = time.time()
    if "1" not in skip:
        part1_selfchecks()
    if "2" not in skip:
        part2_table(10_000 if a.quick else 50_000)
    if "3" not in skip:
        part3_pymeshlab(1 if a.quick else 3)
    print(f"\ntotal time {time.time() - t0:.1f} s")


if __name__ == "__main__":
    main()
