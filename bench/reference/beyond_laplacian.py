"""Experiments for docs/laplacian.md, section "Beyond the thesis" (problems (a)-(e)).

Run:  cd bench/reference && ../../.venv/bin/python beyond_laplacian.py [a b c d e]
All numbers are means over random messages (seeds 0..S-1), CDR over the full message.
Configurations (all with K=ceil(N/70), n_thr=46, n_robust=5, eps=1e-5):
  T   thesis as written: d from M = K - eps I, X_hat = M^-1 L_hat
  TR  T + re-centre each connected component to its original centroid
  TD  T but X_hat = X + M^-1 (L_hat - L) + re-centre
  TZ  T + zero_sum: L_hat - L made zero-sum per component on the changed rows (no drift, still exact)
  G   d from the pure Kirchhoff matrix (eps = 0), exact eps-free "grounded" solve, centroid kept
  GZ  G + zero_sum
  GM  GZ + eq. 7.2.16 margin enforced also in Case 1 (margin_always)
"""
import sys
import time
import numpy as np
from _load import load_mesh
import laplacian_ref as lr
import _attacks as A

MESHES = "/work/shared/meshes/classic/"
CONF = {
    "T": dict(),
    "TR": dict(recentre="component"),
    "TD": dict(solve="delta", recentre="component"),
    "TZ": dict(zero_sum=True),
    "G": dict(lap_eps=0.0, solve="grounded"),
    "GZ": dict(lap_eps=0.0, solve="grounded", zero_sum=True),
    "GM": dict(lap_eps=0.0, solve="grounded", zero_sum=True, margin_always=True),
}


def load(name="bunny.obj"):
    V, F, _ = load_mesh(MESHES + name)
    return V, F


def ex(X, F, side, mode):
    """mode: blind (K, n_thr, eps known; range from the mesh), side (stored d_min/d_max),
    keyed (stored d range + stored pair list)."""
    if mode == "blind":
        return lr.extract(X, F, K=side["K"], n_thr=side["n_thr"], eps=side["lap_eps"], n_bits=side["n_bits"])
    if mode == "side":
        return lr.extract(X, F, side)
    if mode == "keyed":
        return lr.extract(X, F, side, keyed_pairs=True)
    if mode == "keyed-blind":
        return lr.extract(X, F, side, keyed_pairs=True, use_side_range=False)
    raise ValueError(mode)


def dhat_of(V, F, bits, side, conf):
    d = lr.laplacian_lengths(V, F, side["lap_eps"])
    w = 2 * np.asarray(bits) - 1
    dh, _, _ = lr.compute_dhat(d, side["K"], w, side["n_thr"], side["n_robust"], side["d_min"], side["d_max"],
                               conf.get("margin_always", False), conf.get("min_f"))
    return dh


def section_a(S=5):
    print("\n=== (a) float32 storage; model placed at an offset of o * bbox-diag from the origin before embedding")
    V0, F = load()
    diag = lr.bbox_diag(V0)
    print("conf  offset  capacity  max|d_f32-d_hat|/delta  CDR_f32 blind  side")
    for c in ["T", "TZ", "GZ", "GM"]:
        for o in [0, 10, 100, 1000]:
            V = V0 + o * diag
            C = lr.capacity(V, F, eps=CONF[c].get("lap_eps", 1e-5))
            res = []
            for s in range(S):
                bits = np.random.default_rng(s).integers(0, 2, C)
                Xh, side = lr.embed(V, F, bits, **CONF[c])
                Xf = A.f32(Xh)
                dh = dhat_of(V, F, bits, side, CONF[c])
                err = np.abs(lr.laplacian_lengths(Xf, F, side["lap_eps"]) - dh).max() / side["delta"]
                res.append((err, lr.cdr(bits, ex(Xf, F, side, "blind")), lr.cdr(bits, ex(Xf, F, side, "side"))))
            r = np.mean(res, 0)
            print("%-4s %6d %9d %14.3g %16.3f %8.3f" % (c, o, C, r[0], r[1], r[2]))


def section_b(S=6):
    print("\n=== (b) OBJ text round trip (write with fmt, parse back)")
    V0, F = load()
    print("conf  model-scale  fmt     CDR blind (min)   side (min)   max|d_q-d_hat|/delta")
    for scale in [1.0, 0.1]:
        V = V0 * scale
        C = lr.capacity(V, F)
        for c in ["T", "TZ", "GZ", "GM"]:
            for fmt in ["%.6f", "%.9g", "%.17g"]:
                if scale != 1.0 and fmt != "%.6f":
                    continue
                res = []
                for s in range(S):
                    bits = np.random.default_rng(s).integers(0, 2, C)
                    Xh, side = lr.embed(V, F, bits, **CONF[c])
                    Xq = A.text_roundtrip(Xh, fmt)
                    dh = dhat_of(V, F, bits, side, CONF[c])
                    err = np.abs(lr.laplacian_lengths(Xq, F, side["lap_eps"]) - dh).max() / side["delta"]
                    res.append((lr.cdr(bits, ex(Xq, F, side, "blind")), lr.cdr(bits, ex(Xq, F, side, "side")), err))
                r = np.array(res)
                print("%-4s %5.1f  %-6s  %.3f (%.3f)     %.3f (%.3f)   %.3g"
                      % (c, scale, fmt, r[:, 0].mean(), r[:, 0].min(), r[:, 1].mean(), r[:, 1].min(), r[:, 2].mean()))


def section_c(S=5):
    print("\n=== (c) uniform scaling vs stored d_min/d_max (conf GM; side info normalised by a scale)")
    V, F = load()
    C = lr.capacity(V, F, eps=0.0)
    rng = np.random.default_rng(123)
    NORMS = [None, "mean_edge", "bbox", "rms", "median_d"]
    attacks = {
        "none": lambda X: X,
        "x2": lambda X: 2 * X,
        "x0.5": lambda X: 0.5 * X,
        "x1000": lambda X: 1000 * X,
        "x2+noise1e-5": lambda X: A.noise(2 * X, 1e-5, rng),
        "x2+noise5e-5": lambda X: A.noise(2 * X, 5e-5, rng),
        "x2+bend20": lambda X: A.bend(2 * X, 20),
        "x2+bend45": lambda X: A.bend(2 * X, 45),
        "x2+twist45": lambda X: A.twist(2 * X, 45),
        "x2+smooth0.02": lambda X: A.smooth(2 * X, F, 0.02),
    }
    # how much each normaliser moves under the (non-scaling part of the) attacks
    for nm, at in [("noise1e-5", lambda X: A.noise(X, 1e-5, rng)), ("noise5e-5", lambda X: A.noise(X, 5e-5, rng)),
                   ("bend20", lambda X: A.bend(X, 20)), ("bend45", lambda X: A.bend(X, 45)),
                   ("twist45", lambda X: A.twist(X, 45)), ("smooth0.02", lambda X: A.smooth(X, F, 0.02))]:
        Y = at(V)
        print("   relative change of scale under %-10s: mean_edge %+.2e  bbox %+.2e  rms %+.2e  median_d %+.2e" % (
            nm, *[lr.scale_of(Y, F, h) / lr.scale_of(V, F, h) - 1 for h in ["mean_edge", "bbox", "rms", "median_d:0.0"]]))
    print("attack           blind  | side: absolute  mean_edge   bbox     rms   median_d")
    out = {k: [] for k in attacks}
    for s in range(S):
        bits = np.random.default_rng(s).integers(0, 2, C)
        sides = {}
        for sn in NORMS:
            Xh, sides[sn] = lr.embed(V, F, bits, scale_norm=sn, **CONF["GM"])
        for k, at in attacks.items():
            Y = at(Xh)
            out[k].append([lr.cdr(bits, ex(Y, F, sides[None], "blind"))] +
                          [lr.cdr(bits, ex(Y, F, sides[sn], "side")) for sn in NORMS])
    for k in attacks:
        r = np.mean(out[k], 0)
        print("%-16s %.3f  |       %.3f     %.3f     %.3f    %.3f    %.3f" % (k, *r))


def section_c2(S=3):
    print("\n=== (c2) mean-edge-normalised side info + range-factor search (t in [0.9,1.1], keyed pairs)")
    V, F = load()
    rng = np.random.default_rng(321)
    attacks = {
        "x2": lambda X: 2 * X,
        "x2+noise5e-5": lambda X: A.noise(2 * X, 5e-5, rng),
        "x2+bend20": lambda X: A.bend(2 * X, 20),
        "x2+bend45": lambda X: A.bend(2 * X, 45),
        "x2+twist45": lambda X: A.twist(2 * X, 45),
        "x2+smooth0.02": lambda X: A.smooth(2 * X, F, 0.02),
    }
    print("conf attack           norm-seq  norm-keyed  +search-keyed  +search-seq   factor t")
    for c in ["T", "GM"]:
        C = lr.capacity(V, F, eps=CONF[c].get("lap_eps", 1e-5))
        out = {k: [] for k in attacks}
        for s in range(S):
            bits = np.random.default_rng(s).integers(0, 2, C)
            Xh, side = lr.embed(V, F, bits, scale_norm="mean_edge", **CONF[c])
            for k, at in attacks.items():
                Y = at(Xh)
                rs = (0.9, 1.1, 2001)
                b4, det = lr.extract(Y, F, side, keyed_pairs=True, range_search=rs, return_details=True)
                out[k].append([lr.cdr(bits, lr.extract(Y, F, side)),
                               lr.cdr(bits, lr.extract(Y, F, side, keyed_pairs=True)),
                               lr.cdr(bits, b4),
                               lr.cdr(bits, lr.extract(Y, F, side, range_search=rs)),
                               det["range_factor"]])
        for k in attacks:
            print("%-4s %-16s  %.3f     %.3f       %.3f          %.3f        %.4f" % (c, k, *np.mean(out[k], 0)))


def section_d(S=5):
    print("\n=== (d) eps-regularised solve: translation drift and distortion")
    print("mesh        conf  ncomp  drift/diag (max comp)  RMSE/diag  RMSE-after-recentre/diag  maxdisp/diag  "
          "max|d(X_hat)-d_hat|/delta  CDR blind: none  +1diag  +100diag")
    for name in ["bunny.obj", "hand.obj", "cow.obj", "teapot.obj"]:
        V, F = load(name)
        labels = lr._component_labels(len(V), F)
        nc_ = labels.max() + 1
        diag = lr.bbox_diag(V)
        for c in ["T", "TR", "TD", "TZ", "G", "GZ"]:
            C = lr.capacity(V, F, eps=CONF[c].get("lap_eps", 1e-5))
            res = []
            for s in range(S):
                bits = np.random.default_rng(s).integers(0, 2, C)
                Xh, side = lr.embed(V, F, bits, **CONF[c])
                D = Xh - V
                cd = np.stack([np.bincount(labels, D[:, j], nc_) for j in range(3)], 1) / np.bincount(labels)[:, None]
                drift = np.linalg.norm(Xh.mean(0) - V.mean(0)) / diag
                dmaxc = np.linalg.norm(cd, axis=1).max() / diag
                rmse = np.sqrt((D ** 2).sum(1).mean()) / diag
                Dc = D - cd[labels]
                rmse_c = np.sqrt((Dc ** 2).sum(1).mean()) / diag
                maxd = np.linalg.norm(Dc, axis=1).max() / diag
                dh = dhat_of(V, F, bits, side, CONF[c])
                cons = np.abs(lr.laplacian_lengths(Xh, F, side["lap_eps"]) - dh).max() / side["delta"]
                res.append((drift, dmaxc, rmse, rmse_c, maxd, cons,
                            lr.cdr(bits, ex(Xh, F, side, "blind")),
                            lr.cdr(bits, ex(Xh + diag, F, side, "blind")),
                            lr.cdr(bits, ex(Xh + 100 * diag, F, side, "blind")), side["zero_sum_dev"]))
            r = np.mean(res, 0)
            print("%-11s %-4s %5d   %.2e (%.2e)     %.2e   %.2e                 %.2e      %.2e                "
                  "%.3f  %.3f  %.3f   %.2e" % (name, c, nc_, *r))


def section_e(S=4):
    print("\n=== (e) desynchronisation: valid pairs appearing/vanishing (bunny)")
    print("modes: seq = thesis sequential re-detection (eq. 7.3.21); keyed = bits read from the stored pair list;")
    print("       resync = seq + count-guided resync (needs n_bits only); blind/side = bin range from mesh / stored")
    V, F = load()
    rng = np.random.default_rng(7)
    attacks = {
        "obj %.6f": lambda X: A.text_roundtrip(X, "%.6f"),
        "noise 2e-5": lambda X: A.noise(X, 2e-5, rng),
        "noise 5e-5": lambda X: A.noise(X, 5e-5, rng),
        "noise 1e-4": lambda X: A.noise(X, 1e-4, rng),
        "bend 20deg": lambda X: A.bend(X, 20),
        "bend 45deg": lambda X: A.bend(X, 45),
        "smooth 0.02": lambda X: A.smooth(X, F, 0.02),
    }
    confs = {"T": CONF["T"], "GM": CONF["GM"], "GM+auto_thr": dict(CONF["GM"], auto_thr=True)}
    print("conf         attack        chg(blind) chg(side) | seq-blind resync-blind keyed-blind | seq-side resync-side keyed-side"
          " | rep3: seq-side keyed-side")

    def dec(b, m):
        b = np.concatenate([b, np.full(max(0, 3 * m - len(b)), -1)])[:3 * m].reshape(3, m)
        return ((b == 1).sum(0) >= 2).astype(int)

    for cn, conf in confs.items():
        C0 = lr.capacity(V, F, eps=conf.get("lap_eps", 1e-5))
        acc = {k: [] for k in attacks}
        gaps = []
        for s in range(S):
            bits = np.random.default_rng(s).integers(0, 2, C0)
            m = len(bits) // 3
            msg = bits[:m]
            full = np.concatenate([np.tile(msg, 3), bits[3 * m:]])   # interleaved repetition-3 + filler
            Xh, side = lr.embed(V, F, full, **conf)
            gaps.append((side["n_thr"], side["thr_gap"], side["capacity"]))
            valid0 = lr.extract(Xh, F, side, return_details=True)[1]["f"] >= side["n_thr"]
            for k, at in attacks.items():
                Y = at(Xh)
                r = []
                outs = []
                for usr in (False, True):
                    sq, det = lr.extract(Y, F, side, use_side_range=usr, return_details=True)
                    r.append(int(np.count_nonzero((det["f"] >= side["n_thr"]) != valid0)))
                    rs = lr.extract(Y, F, side, use_side_range=usr, resync_count=True)
                    ky = lr.extract(Y, F, side, use_side_range=usr, keyed_pairs=True)
                    outs.append((sq, rs, ky))
                r += [lr.cdr(full, b) for b in outs[0]] + [lr.cdr(full, b) for b in outs[1]]
                r += [lr.cdr(msg, dec(outs[1][0], m)), lr.cdr(msg, dec(outs[1][2], m))]
                acc[k].append(r)
        if conf.get("auto_thr"):
            g = np.array(gaps)
            print("   auto_thr: n_thr chosen %s, gap %s, capacity %s" % (sorted(set(g[:, 0])), sorted(set(g[:, 1])), sorted(set(g[:, 2]))))
        for k in attacks:
            r = np.mean(acc[k], 0)
            print("%-12s %-13s %6.2f %9.2f    |  %.3f     %.3f       %.3f      |  %.3f     %.3f      %.3f    |  %.3f  %.3f"
                  % (cn, k, *r))


def section_f(S=3):
    print("\n=== (f) editing surrogate (bend = LBS-style joint, thesis Table 7.2 analogue), range blind vs stored")
    print("mesh       conf  attack        CDR blind  side  keyed   frac(|d'-d|>delta/2)")
    for name in ["hand.obj", "bunny.obj"]:
        V, F = load(name)
        ax = int(np.argmax(np.ptp(V, 0)))
        for c in ["T", "GM"]:
            C = lr.capacity(V, F, eps=CONF[c].get("lap_eps", 1e-5))
            for deg, band in [(20, 0.2), (45, 0.2), (90, 0.2), (45, 0.05)]:
                r = []
                for s in range(S):
                    bits = np.random.default_rng(s).integers(0, 2, C)
                    Xh, side = lr.embed(V, F, bits, **CONF[c])
                    Y = A.bend(Xh, deg, axis=ax, band=band)
                    d0 = lr.laplacian_lengths(Xh, F, side["lap_eps"])
                    d1 = lr.laplacian_lengths(Y, F, side["lap_eps"])
                    r.append((lr.cdr(bits, ex(Y, F, side, "blind")), lr.cdr(bits, ex(Y, F, side, "side")),
                              lr.cdr(bits, ex(Y, F, side, "keyed")), np.mean(np.abs(d1 - d0) > 0.5 * side["delta"])))
                print("%-10s %-4s bend %3d b%.2f    %.3f   %.3f  %.3f   %.3f" % (name, c, deg, band, *np.mean(r, 0)))


if __name__ == "__main__":
    which = sys.argv[1:] or ["a", "b", "c", "c2", "d", "e", "f"]
    for w in which:
        t = time.time()
        globals()["section_" + w]()
        print("   [section %s: %.0f s]" % (w, time.time() - t))
