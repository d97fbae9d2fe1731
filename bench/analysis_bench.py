"""Bench: the ch. 3-5 analysis (meshmark.analysis) against plain numpy versions in the same process.

    .venv/bin/python bench/analysis_bench.py [--small]

Cases (targets from issue 12):
* level: quantization_level (E_appr, 1 degree) on the shared Elephant and Bunny midpoint-subdivided
  to >= 2M triangles (2.56M and 4.44M; --small: the Bunny): <= 0.5 s (thesis: 56 s in Matlab for the
  2.2M-triangle Welsh Dragon). numpy: heights from edge lengths and cross products, eq. 4.3.21, plus the exact E_mesh at
  that level (the check that decides whether the closed form holds).
* ch3 fit: degradation_model on the Bunny (5 dithered double-pattern samples x 3 weightings + the
  logistic fits): <= 0.2 s. numpy: the same dither (uint64 view, the same random words), normals,
  angles, area and dihedral-Gaussian weights (edge pairing by sort), the same scipy fits; numpy draws
  its own random words, so its a, b agree statistically, not bit for bit.
* curvature: curvature_model on the Bunny (3 directions x 20 levels): <= 1 s. numpy: displacement,
  interior angles with arctan2, angle sums by bincount, per level.
Prints best-of wall times and the process CPU times (this machine is shared: CPU time is what the
code costs, wall time what it took), the numpy time and the ratio, and checks that both give the same
numbers.
"""
from __future__ import annotations

import argparse
import math
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import SHARED, big_bunny  # noqa: E402
from _common import best_of_clocks as best_of  # noqa: E402  (wall, CPU, result)
from _common import big_elephant as _big_elephant  # noqa: E402

import meshmark  # noqa: E402
from meshmark import _core  # noqa: E402
from meshmark import analysis as A  # noqa: E402


def report(name, mm, ref, target):
    (w, c, _), (wn, cn, _) = mm, ref
    print(f"  {name}: meshmark {w:.3f} s wall / {c:.3f} s CPU   numpy {wn:.3f} s wall / {cn:.3f} s CPU   "
          f"ratio {wn / w:.1f}x wall, {cn / c:.1f}x CPU   (target <= {target} s)")


# --- numpy references ------------------------------------------------------------------------------

def np_heights(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    area2 = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    e = np.stack([np.linalg.norm(b - c, axis=1), np.linalg.norm(c - a, axis=1), np.linalg.norm(a - b, axis=1)], 1)
    h = np.sort(area2[:, None] / e, axis=1)
    return h[area2 > 0]


def np_expected(r):
    r = np.asarray(r, float)
    out = np.empty_like(r)
    s = r < 0.05
    x = r[s]
    x2 = x * x
    out[s] = x * (0.5 + x2 * (1 / 12 + x2 * (-1 / 30 + x2 * (-5 / 168 + x2 * (1 / 30 + x2 * 5 / 132)))))
    x = r[~s]
    a, b = 1 - x, 1 + x
    with np.errstate(divide="ignore", invalid="ignore"):
        L = ((1 - 2 * x) * np.log(a * a + x * x) + 2 * b * b * np.log(b) - (1 + 2 * x) * np.log(b * b + x * x)
             - np.where(x == 1, 0, 2 * a * a * np.log(np.abs(a))))
        E = L / (8 * x * x) + b / (2 * x) * np.arctan(x / b) - np.where(x == 1, 0, a / (2 * x) * np.arctan(x / a))
    out[~s] = E + np.where(x > 1, np.pi * (x - 1) / (2 * x), 0)
    return out


def np_level(V, F, tol_deg, eta=A.ETA):
    h = np_heights(V, F)
    L = np.ptp(V, axis=0).max()
    M = len(h)
    eps = math.radians(tol_deg)
    S = L * eta * (1 / h).sum()
    i = math.ceil(-2 - math.log2(M * eps / S))                   # eq. 4.3.21
    l = L * 2.0 ** -(i + 1)
    e_exact = eta * np_expected(l / h).sum() / M                  # the validity check
    return i, e_exact


def np_dither64(V, t, words):
    u = V.view(np.uint64)
    low = np.uint64((1 << (64 - t)) - 1) if t < 64 else np.uint64(0)
    return ((u & ~low) | (words & low)).view(np.float64)


def np_min_dihedral(V, F):
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    k = len(F)
    a = F.ravel()
    b = F[:, [1, 2, 0]].ravel()
    key = np.minimum(a, b).astype(np.int64) << 32 | np.maximum(a, b)
    face = np.repeat(np.arange(k), 3)
    o = np.argsort(key, kind="stable")
    key, face = key[o], face[o]
    pair = np.nonzero(key[1:] == key[:-1])[0]
    f, g = face[pair], face[pair + 1]
    ang = np.degrees(np.arctan2(np.linalg.norm(np.cross(n[f], n[g]), axis=1), (n[f] * n[g]).sum(1)))
    x = np.full(k, np.inf)
    np.minimum.at(x, f, ang)
    np.minimum.at(x, g, ang)
    return x


def np_ch3(V, F, seed=0):
    n1 = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    area = 0.5 * np.linalg.norm(n1, axis=1)
    x = np_min_dihedral(V, F)
    wd = np.where(np.isfinite(x), np.exp(-x ** 2 / (2 * 3.5 ** 2)) / math.sqrt(2 * math.pi * 3.5 ** 2), 0)
    samples = {w: [] for w in A.WEIGHTINGS}
    for t in A.FIT_LEVELS:
        rng = np.random.default_rng([seed, t])  # numpy's own random words (the fit agrees statistically)
        words = rng.integers(0, np.iinfo(np.uint64).max, size=V.shape, dtype=np.uint64, endpoint=True)
        V2 = np_dither64(V, t, words)
        n2 = np.cross(V2[F[:, 1]] - V2[F[:, 0]], V2[F[:, 2]] - V2[F[:, 0]])
        with np.errstate(invalid="ignore", over="ignore"):
            ang = np.arctan2(np.linalg.norm(np.cross(n1, n2), axis=1), (n1 * n2).sum(1))
        ok = np.isfinite(ang) & (np.linalg.norm(n2, axis=1) > 0)
        for w, wt in zip(A.WEIGHTINGS, (np.ones(len(F)), area, wd)):
            samples[w].append(float((wt[ok] * ang[ok]).sum() / wt[ok].sum()))
    return {w: A.fit_logistic(A.FIT_LEVELS, samples[w]) for w in A.WEIGHTINGS}


def np_angle_sum(V, F):
    S = np.zeros(len(V))
    for k in range(3):
        a, b, c = V[F[:, k]], V[F[:, (k + 1) % 3]], V[F[:, (k + 2) % 3]]
        u, v = b - a, c - a
        S += np.bincount(F[:, k], np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), (u * v).sum(1)), len(V))
    return S


def np_curvature(V, F, interior, levels=A.SWEEP_LEVELS, seed=0):
    n = np.zeros_like(V)
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    fn /= np.linalg.norm(fn, axis=1)[:, None]
    for k in range(3):
        np.add.at(n, F[:, k], fn)
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
    axis = np.argmin(np.abs(n), axis=1)
    e1 = np.cross(n, np.eye(3)[axis])
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(n, e1)
    L = np.ptp(V, axis=0).max()
    S0 = np_angle_sum(V, F)
    rng = np.random.default_rng(seed)
    out = {}
    for d in A.DIRECTIONS:
        k = []
        for t in levels:
            s = rng.uniform(-1, 1, len(V)) * L * 2.0 ** (1 - t)
            if d == "normal":
                u = n
            elif d == "tangential":
                phi = rng.uniform(0, 2 * np.pi, len(V))
                u = np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2
            else:
                u = rng.normal(size=V.shape)
                u /= np.linalg.norm(u, axis=1)[:, None]
            k.append(np.abs(np_angle_sum(V + s[:, None] * u, F) - S0)[interior].mean())
        out[d] = A.fit_linear(levels, k)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--small", action="store_true", help="the level case on the Bunny instead of >= 2M triangles")
    args = ap.parse_args()
    bunny = meshmark.read_mesh(SHARED / "classic" / "bunny.obj")
    keep = bunny.referenced().astype(bool)
    new = np.cumsum(keep) - 1
    bunny = meshmark.Mesh(bunny.V[keep], new[bunny.F])  # the numpy versions ignore unreferenced vertices
    bigs = [("bunny", bunny)] if args.small else [("elephant x64", _big_elephant(0, 2_000_000)), ("bunny x64", big_bunny(2_000_000))]
    for name, big in bigs:
        V, F = big.V, np.ascontiguousarray(big.F, np.int32)
        print(f"level: {name}, {len(F)} triangles")
        mm = best_of(lambda: A.quantization_level((V, F), 1.0))
        ref = best_of(lambda: np_level(V, F, 1.0))
        lvl, (lvl_np, e_np) = mm[2], ref[2]
        det = A.quantization_details((V, F), 1.0)
        assert lvl == lvl_np and abs(det["e_exact"] - e_np) <= 1e-9 * e_np, (lvl, lvl_np, det["e_exact"], e_np)
        report(f"level {lvl}", mm, ref, 0.5)

    Vb, Fb = bunny.V, np.ascontiguousarray(bunny.F, np.int32)
    print(f"ch3 fit: Bunny, {len(Fb)} triangles, 5 samples x 3 weightings")
    A.fit_logistic(A.FIT_LEVELS, A.logistic(np.array(A.FIT_LEVELS), 20, -1, 1.57))  # import scipy outside the timing
    mm = best_of(lambda: A.degradation_model((Vb, Fb)), 5)
    ref = best_of(lambda: np_ch3(Vb, Fb), 5)
    report("fit", mm, ref, 0.2)
    r, rn = mm[2], ref[2]
    for w in A.WEIGHTINGS:
        print(f"    {w:<8} a {r[w]['a']:.3f} / numpy {rn[w]['a']:.3f}   b {r[w]['b']:.3f} / {rn[w]['b']:.3f}")

    print("curvature: Bunny, 3 directions x 20 levels")
    g = A.gaussian_curvature((Vb, Fb))
    mm = best_of(lambda: A.curvature_model((Vb, Fb)))
    ref = best_of(lambda: np_curvature(Vb, Fb, g["interior"]))
    report("sweep", mm, ref, 1.0)
    r, rn = mm[2], ref[2]
    for d in A.DIRECTIONS:
        print(f"    {d:<10} a {r[d]['a']:.3f} / numpy {rn[d]['a']:.3f}   b {r[d]['b']:.2f} / {rn[d]['b']:.2f}")


if __name__ == "__main__":
    main()
