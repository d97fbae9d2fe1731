"""Pure-numpy reference implementations of the radial (vertex-norm histogram)
watermarks and of the specific steganalyzer of Yang's thesis, chapter 6.

    cho_mean_embed / cho_mean_extract          Cho, Prost & Jung 2007, Method I
    cho_variance_embed / cho_variance_extract  Cho, Prost & Jung 2007, Method II
    yang_radial_embed / yang_radial_extract    Yang 2013, sections 6.1-6.2
    cho_steganalysis                           Yang 2013, section 6.4

Reference = readable and exact, vectorized over vertices (the only Python
loops are over bisection steps, over the optional re-synchronisation
iterations and over the candidate bin numbers K of the steganalyzer).  The full specification, every choice
made where the sources are vague, and measured results are in
docs/radial.md; equation numbers below are the thesis' (6.x.y) or refer to
the Cho et al. procedure as summarised in thesis section 2.2.2 and
docs/radial.md ("Cho step n").

Conventions shared by all functions
-----------------------------------
* ``V`` is an (n, 3) float array of vertex positions; faces are never needed.
* Message bits are given as 0/1; bit 1 <-> w = +1, bit 0 <-> w = -1.
  For Cho: w = +1 raises the bin statistic (mean above 1/2, or "variance"
  above 1/3), w = -1 lowers it (thesis Figs. 2.4 / 2.5 (c) and (a)).
  For Yang: w = +1 <-> |B'_k| > |B'_{k+1}|, w = -1 <-> |B'_{k+1}| >= |B'_k|
  (eq. 6.2.10).
* Vertices are only moved radially about the origin (theta, phi of eq. 6.1.1
  kept): v' = o + (rho'/rho) (v - o).
"""
from __future__ import annotations

import math
import time

import numpy as np

# ---------------------------------------------------------------------------
# thesis constants
# ---------------------------------------------------------------------------

#: Table 6.1 of the thesis: model -> (#vertices, #faces, n_thr); K = 400.
YANG_TABLE_6_1 = {
    "bunny": (34835, 69666, 43),
    "rabbit": (70658, 141312, 80),
    "venus": (100759, 201514, 100),
    "dragon": (50000, 100000, 75),
    "cow": (2904, 5804, 8),
}

#: Table 6.2 of the thesis (steganalysis of section 6.4, K in [1, 500]).
TABLE_6_2 = [
    # method, #bits, #marked models, accuracy of K, detection accuracy
    ("Cho's", 64, 443, 0.9684, 0.9458),
    ("Cho's", 100, 386, 0.9663, 0.9301),
    ("Ours", 64, 377, 0.0065, 0.0663),
    ("Ours", 100, 371, 0.0, 0.0674),
]


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------

def _pm1(bits):
    b = np.asarray(bits).astype(np.int64).ravel()
    if b.size and not np.isin(b, (0, 1)).all():
        raise ValueError("bits must be 0/1")
    return 2 * b - 1


def _radial_rescale(V, origin, rho, rho_new):
    """Move vertices along their ray from `origin` so that |v - o| = rho_new.

    Vertices whose radius is unchanged are copied bit-exactly (so the
    reference points rho_min / rho_max are kept exactly)."""
    out = np.array(V, dtype=np.float64, copy=True)
    m = (rho_new != rho) & (rho > 0)
    if m.any():
        out[m] = origin + (out[m] - origin) * (rho_new[m] / rho[m])[:, None]
    return out


def rmse(V0, V1):
    """Vertex-wise RMSE sqrt(mean |v1 - v0|^2) (the thesis uses Metro's
    surface RMSE instead; see docs/radial.md)."""
    d = np.asarray(V1, float) - np.asarray(V0, float)
    return float(np.sqrt(np.mean(np.sum(d * d, axis=1))))


def correlation(bits_true, bits_found):
    """Correlation coefficient C(w, w') of eq. 6.3.11 (on +-1 symbols)."""
    a = _pm1(bits_true).astype(float)
    b = _pm1(bits_found).astype(float)
    a -= a.mean()
    b -= b.mean()
    den = math.sqrt(float((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / den) if den > 0 else 0.0


def cdr(bits_true, bits_found):
    """Correct detection rate: fraction of bits decoded correctly."""
    a = np.asarray(bits_true).ravel()
    b = np.asarray(bits_found).ravel()
    return float(np.mean(a == b))


# ---------------------------------------------------------------------------
# Cho, Prost & Jung 2007 (thesis section 2.2.2, Figs. 2.4-2.5)
# ---------------------------------------------------------------------------

def cho_center(V):
    """Cho step 1: centre of gravity = plain mean of the vertex positions."""
    return np.asarray(V, dtype=np.float64).mean(axis=0)


def cho_bins(rho, n_bins):
    """Cho step 2-3: split [rho_min, rho_max] into n_bins equal ranges and
    normalise every norm to [0, 1] inside its bin using the *bin range*:

        B_n = { rho_i : rho_min + n W < rho_i < rho_min + (n+1) W },
        W = (rho_max - rho_min) / N,  n = 0..N-1,
        x_i = (rho_i - (rho_min + n W)) / W.

    The two reference vertices (rho == rho_min or rho == rho_max) belong to
    no bin (index -1) and are never moved, so rho_min and rho_max survive
    embedding exactly.  (Norms lying exactly on an interior boundary, a
    zero-measure event, are put in the upper bin.)

    Returns (idx, x, rho_min, W)."""
    rho = np.asarray(rho, dtype=np.float64)
    rmin, rmax = float(rho.min()), float(rho.max())
    if not rmax > rmin:
        raise ValueError("degenerate vertex-norm range")
    W = (rmax - rmin) / n_bins
    idx = np.floor((rho - rmin) / W).astype(np.int64)
    np.clip(idx, 0, n_bins - 1, out=idx)
    idx[(rho == rmin) | (rho == rmax)] = -1
    lo = rmin + W * np.maximum(idx, 0)
    x = np.clip((rho - lo) / W, 0.0, 1.0)
    return idx, x, rmin, W


def _cho_stat(x, idx, n_bins, k_bin, method, guard=0.0):
    """Per-bin statistic of the mapped normalised norms for exponents k_bin.

    mean:     mean_j x_j^k                                 (target 1/2)
    variance: mean_j |2 x_j - 1|^(2k), i.e. the second moment of
              y = sign(2x-1) |2x-1|^k on [-1, 1]           (target 1/3)
    (with guard > 0 the mapped values of bins with k != 1 are first clipped
    to [guard, 1 - guard], see _cho_map)
    """
    v = idx >= 0
    xi, bi = x[v], idx[v]
    k = k_bin[bi]
    if guard > 0.0:
        xm = _cho_map(xi, k, method, guard)
        y = xm if method == "mean" else (2.0 * xm - 1.0) ** 2
    elif method == "mean":
        y = xi ** k
    else:
        y = np.abs(2.0 * xi - 1.0) ** (2.0 * k)
    s = np.bincount(bi, weights=y, minlength=n_bins)
    c = np.bincount(bi, minlength=n_bins)
    return s / np.maximum(c, 1), c


def _cho_map(x, k, method, guard=0.0):
    """Histogram mapping function (Cho's Fig. 2.4/2.5 mapping).

    guard > 0 (NOT in the paper): mapped values of bins with k != 1 are
    clipped to [guard, 1 - guard] so that the tiny shift of the centre seen
    by the blind detector cannot carry a vertex that the mapping crowded
    against a bin end into the neighbouring bin (docs/radial.md)."""
    if method == "mean":
        xm = x ** k                                      # x' = x^k on [0, 1]
    else:
        y = 2.0 * x - 1.0                                # [0,1] -> [-1,1]
        y = np.sign(y) * np.abs(y) ** k                  # y' = sgn(y)|y|^k
        xm = np.clip(0.5 * (y + 1.0), 0.0, 1.0)          # back to [0, 1]
    if guard > 0.0:
        xm = np.where(k != 1.0, np.clip(xm, guard, 1.0 - guard), xm)
    return xm


def _cho_embed_once(V, bits, n_bins, alpha, delta_k, method, k_max, center,
                    guard=0.0):
    t0 = time.perf_counter()
    V = np.asarray(V, dtype=np.float64)
    w = _pm1(bits)
    if n_bins is None:
        n_bins = len(w)
    if len(w) > n_bins:
        raise ValueError("more bits than bins")
    ref = 0.5 if method == "mean" else 1.0 / 3.0
    o = cho_center(V) if center is None else np.asarray(center, float)
    rho = np.linalg.norm(V - o, axis=1)
    idx, x, rmin, W = cho_bins(rho, n_bins)

    # bins n >= len(w) carry no bit: k = 1 (identity)
    wb = np.zeros(n_bins, dtype=np.int64)
    wb[: len(w)] = w
    carry = wb != 0

    # Cho step 4: k_n is moved from 1 in steps of delta_k (down for w=+1,
    # up for w=-1) until the statistic passes ref + alpha (w=+1) or
    # ref - alpha (w=-1).  The statistic is monotone (decreasing) in k, so
    # "first step m that satisfies the condition" is found by a vectorized
    # bisection on the integer step count m (exactly the same m as the
    # sequential iteration).
    m_up = int(round((k_max - 1.0) / delta_k))          # k = 1 + m dk <= k_max
    m_dn = int(round((1.0 - delta_k) / delta_k))        # k = 1 - m dk >= dk > 0
    m_hi = np.where(wb > 0, m_dn, m_up)

    def k_of(m):
        k = np.where(wb > 0, 1.0 - m * delta_k, 1.0 + m * delta_k)
        return np.where(carry, k, 1.0)

    def ok(m):
        st, _ = _cho_stat(x, idx, n_bins, k_of(m), method, guard)
        return np.where(wb > 0, st >= ref + alpha, st <= ref - alpha)

    zero = np.zeros(n_bins, dtype=np.int64)
    ok0 = ok(zero)
    okhi = ok(m_hi)
    lo = zero.copy()                     # invariant: ok(lo) False (unless ok0)
    hi = m_hi.copy()                     # invariant: ok(hi) True (unless fail)
    todo = carry & ~ok0 & okhi
    while True:
        act = todo & (hi - lo > 1)
        if not act.any():
            break
        mid = np.where(act, (lo + hi) // 2, lo)
        o_mid = ok(mid)
        hi = np.where(act & o_mid, mid, hi)
        lo = np.where(act & ~o_mid, mid, lo)
    m = np.where(ok0, 0, hi)
    k_bin = np.where(carry, k_of(m), 1.0)

    counts = np.bincount(idx[idx >= 0], minlength=n_bins)
    failed = carry & ((counts == 0) | ~(ok0 | okhi))

    # Cho step 5: map, denormalise with the same bin range, back to xyz.
    v = idx >= 0
    x_new = x.copy()
    x_new[v] = _cho_map(x[v], k_bin[idx[v]], method, guard)
    rho_new = rho.copy()
    changed = v & (k_bin[np.maximum(idx, 0)] != 1.0)
    rho_new[changed] = rmin + W * (idx[changed] + x_new[changed])
    V_new = _radial_rescale(V, o, rho, rho_new)

    st_after, _ = _cho_stat(x_new, idx, n_bins, np.ones(n_bins), method)
    info = {
        "method": "cho_" + method,
        "n_bins": n_bins,
        "alpha": alpha,
        "delta_k": delta_k,
        "k": k_bin,
        "bin_counts": counts,
        "stat_before": _cho_stat(x, idx, n_bins, np.ones(n_bins), method)[0],
        "stat_after": st_after,
        "failed_bins": np.flatnonzero(failed),
        "center": o,
        "rho_min": rmin,
        "rho_max": rmin + W * n_bins,
        "seconds": time.perf_counter() - t0,
    }
    return V_new, info


def _cho_embed(V, bits, n_bins, alpha, delta_k, method, k_max, center,
               center_iters, guard=0.0):
    """Single-shot embedding (the paper) followed, if center_iters > 0, by a
    fixed-point re-synchronisation that is NOT in the paper: the centre of
    gravity of the marked mesh differs slightly from the one used to embed,
    so the blind detector sees shifted bins; re-embedding the *original*
    mesh about the marked mesh's centre, until the two agree, makes the
    detector see exactly the embedded statistics (docs/radial.md)."""
    t0 = time.perf_counter()
    Vm, info = _cho_embed_once(V, bits, n_bins, alpha, delta_k, method,
                               k_max, center, guard)
    drift = float(np.linalg.norm(cho_center(Vm) - info["center"]))
    best = (drift, Vm, info)
    it = 0
    while it < center_iters and drift > 0.0:
        Vm, info = _cho_embed_once(V, bits, n_bins, alpha, delta_k, method,
                                   k_max, cho_center(Vm), guard)
        drift = float(np.linalg.norm(cho_center(Vm) - info["center"]))
        it += 1
        if drift < best[0]:
            best = (drift, Vm, info)
    drift, Vm, info = best               # the iterate with the smallest drift
    info["center_iters"] = it
    info["center_drift"] = drift
    info["seconds"] = time.perf_counter() - t0
    return Vm, info


def _cho_extract(V, n_bits, n_bins, method, center):
    V = np.asarray(V, dtype=np.float64)
    if n_bins is None:
        n_bins = n_bits
    ref = 0.5 if method == "mean" else 1.0 / 3.0
    o = cho_center(V) if center is None else np.asarray(center, float)
    rho = np.linalg.norm(V - o, axis=1)
    idx, x, _, _ = cho_bins(rho, n_bins)
    st, c = _cho_stat(x, idx, n_bins, np.ones(n_bins), method)
    # decision: statistic > ref -> w = +1 (bit 1), else w = -1 (bit 0);
    # an empty bin decodes as 0 (and is an erasure).
    bits = (st > ref).astype(np.int64)
    return bits[:n_bits], {"stat": st, "bin_counts": c, "center": o}


def cho_mean_embed(V, bits, n_bins=None, alpha=0.04, delta_k=0.001,
                   k_max=100.0, center=None, center_iters=0, guard=0.0):
    """Cho et al. Method I: mean of the normalised norms of bin n is pushed
    to >= 1/2 + alpha (bit 1) or <= 1/2 - alpha (bit 0) by x' = x^k_n.
    n_bins defaults to len(bits) (one bit per bin, 64 in the thesis).
    center_iters > 0 enables the centre re-synchronisation and guard > 0
    the bin-end guard band (neither is in the paper; see _cho_embed and
    _cho_map)."""
    return _cho_embed(V, bits, n_bins, alpha, delta_k, "mean", k_max, center,
                      center_iters, guard)


def cho_mean_extract(V, n_bits, n_bins=None, center=None):
    """Blind detection of Method I: bit = [mean_n > 1/2]."""
    return _cho_extract(V, n_bits, n_bins, "mean", center)


def cho_variance_embed(V, bits, n_bins=None, alpha=0.16, delta_k=0.001,
                       k_max=100.0, center=None, center_iters=0, guard=0.0):
    """Cho et al. Method II: with y = 2x - 1 in [-1, 1] (uniform -> mean 0,
    variance E[y^2] = 1/3), y' = sgn(y)|y|^k_n until E[y'^2] >= 1/3 + alpha
    (bit 1) or <= 1/3 - alpha (bit 0).  The thesis (section 8.2) draws
    alpha uniformly in [0.12, 0.20]; the default 0.16 is its midpoint."""
    return _cho_embed(V, bits, n_bins, alpha, delta_k, "variance", k_max,
                      center, center_iters, guard)


def cho_variance_extract(V, n_bits, n_bins=None, center=None):
    """Blind detection of Method II: bit = [E[(2x-1)^2] over bin n > 1/3]."""
    return _cho_extract(V, n_bits, n_bins, "variance", center)


# ---------------------------------------------------------------------------
# Yang 2013, sections 6.1-6.2: radial histogram, bin-pair counts
# ---------------------------------------------------------------------------

def principal_axis(V):
    """First principal axis of the vertex set with the project's sign rule:
    the axis is oriented so that the third central moment of the
    projections onto it is positive.  (If that moment is exactly 0 the
    component of largest magnitude is made positive.)

    Returns (centroid, unit axis u, projections p = (v - c) . u)."""
    V = np.asarray(V, dtype=np.float64)
    c = V.mean(axis=0)
    D = V - c
    C = D.T @ D / len(V)
    evals, evecs = np.linalg.eigh(C)
    u = evecs[:, int(np.argmax(evals))].copy()
    p = D @ u
    m3 = float(np.mean(p ** 3))
    if m3 < 0 or (m3 == 0 and u[int(np.argmax(np.abs(u)))] < 0):
        u, p = -u, -p
    return c, u, p


def yang_origin(V, mode="axis"):
    """Section 6.1.1: origin = average of the right-most half of the vertices
    projected on the principal axis.

    mode="axis"     (default) the origin is the point of the axis at the mean
                    projection of the floor(N/2) vertices with the largest
                    projections ("a point computed on the principal axis");
    mode="vertices" the 3-D mean of those same vertices."""
    c, u, p = principal_axis(V)
    n = len(p)
    h = n // 2
    top = np.argpartition(p, n - h)[n - h:]
    if mode == "axis":
        return c + float(np.mean(p[top])) * u
    if mode == "vertices":
        return np.asarray(V, float)[top].mean(axis=0)
    raise ValueError("mode must be 'axis' or 'vertices'")


def yang_default_nthr(n_vertices, K=400):
    """Proposed n_thr for meshes outside Table 6.1 (the thesis gives no rule):
    least-squares power law through the five Table 6.1 pairs (N, n_thr),
    fitted in log-log at K = 400, and scaled by 400/K so that n_thr stays
    the same fraction of the mean population 2N/K of a bin pair:

        n_thr = max(1, round(0.0245 * N**0.726 * 400 / K))

    Table 6.1 -> rule: Bunny 43 -> 49, Rabbit 80 -> 81, Venus 100 -> 105,
    Dragon 75 -> 63, Cow 8 -> 8 (see docs/radial.md)."""
    return max(1, int(round(0.0245 * float(n_vertices) ** 0.726 * 400.0 / K)))


def _yang_hist(rho, K):
    """Eqs. 6.1.2-6.1.3: K bins of width (rho_max - rho_min)/K, half open,
    rho_max put in B_K.  Returns (idx 0-based, rho_min, delta, edges)."""
    rmin, rmax = float(rho.min()), float(rho.max())
    if not rmax > rmin:
        raise ValueError("degenerate radius range")
    d = (rmax - rmin) / K
    idx = np.floor((rho - rmin) / d).astype(np.int64)
    np.clip(idx, 0, K - 1, out=idx)
    edges = rmin + d * np.arange(K + 1)
    return idx, rmin, d, edges


def yang_pairs(K):
    """0-based first bins of the pairs (B_2,B_3), (B_4,B_5), ...: B_1 and
    B_K never used, B_{K-1} dropped too when K is odd.  Capacity
    floor((K-2)/2) (section 6.3.1)."""
    return np.arange(1, K - 2, 2) if K % 2 == 0 else np.arange(1, K - 3, 2)


def _ranges(starts, lengths):
    """Concatenation of arange(s, s+l) for all (s, l), vectorized."""
    lengths = np.asarray(lengths, dtype=np.int64)
    total = int(lengths.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    off = np.repeat(np.asarray(starts, np.int64) - np.cumsum(lengths) + lengths,
                    lengths)
    return off + np.arange(total, dtype=np.int64)


def yang_radial_embed(V, bits, K=400, n_thr=None, origin_mode="axis",
                      origin_iters=0):
    """Yang's histogram-pair watermark (sections 6.1.1-6.1.2).

    Bit i goes to the i-th embeddable pair (|B_k| + |B_{k+1}| >= 1,
    eq. 6.1.4) in order of increasing radius.  For w = -1 the n_mov largest
    radii of B_k are moved into B_{k+1} (eq. 6.1.5); for w = +1 the n_mov
    smallest radii of B_{k+1} are moved into B_k (mirror image).  n_mov by
    cases 1-3 / eq. 6.1.7 so that the count difference reaches n_thr
    (eq. 6.1.6).

    origin_iters > 0: fixed-point re-synchronisation of the origin (not in
    the thesis), as for Cho's centre: re-embed the original mesh about the
    origin recomputed from the marked mesh until the two agree (at most
    origin_iters times; the iterate with the smallest drift is returned:
    on classic/cow.obj the iteration falls into a 2-cycle)."""
    t0 = time.perf_counter()
    V = np.asarray(V, dtype=np.float64)
    Vm, info = _yang_embed_once(V, bits, K, n_thr, yang_origin(V, origin_mode))
    drift = float(np.linalg.norm(yang_origin(Vm, origin_mode) - info["origin"]))
    best = (drift, Vm, info)
    it = 0
    while it < origin_iters and drift > 0.0:
        Vm, info = _yang_embed_once(V, bits, K, n_thr,
                                    yang_origin(Vm, origin_mode))
        drift = float(np.linalg.norm(yang_origin(Vm, origin_mode)
                                     - info["origin"]))
        it += 1
        if drift < best[0]:
            best = (drift, Vm, info)
    drift, Vm, info = best               # the iterate with the smallest drift
    info["origin_iters"] = it
    info["origin_drift"] = drift
    info["seconds"] = time.perf_counter() - t0
    return Vm, info


def _yang_embed_once(V, bits, K, n_thr, o):
    w = _pm1(bits)
    N = len(V)
    if n_thr is None:
        n_thr = yang_default_nthr(N, K)
    rho = np.linalg.norm(V - o, axis=1)                  # eq. 6.1.1
    idx, rmin, d, edges = _yang_hist(rho, K)             # eqs. 6.1.2-6.1.3

    order = np.argsort(rho, kind="stable")
    rs = rho[order]
    bs = idx[order]                                      # non-decreasing
    starts = np.searchsorted(bs, np.arange(K), side="left")
    ends = np.searchsorted(bs, np.arange(K), side="right")
    cnt = ends - starts

    pairs = yang_pairs(K)
    emb = pairs[(cnt[pairs] + cnt[pairs + 1]) >= 1]      # eq. 6.1.4
    if len(w) > len(emb):
        raise ValueError("capacity %d < %d bits" % (len(emb), len(w)))
    a = emb[: len(w)]                                    # B_k   (0-based)
    b = a + 1                                            # B_k+1
    na, nb = cnt[a], cnt[b]
    T = int(n_thr)

    # n_mov, cases 1-3 (w = -1 as written; w = +1 mirrored)
    src = np.where(w < 0, na, nb)        # size of the bin that gives
    dst = np.where(w < 0, nb, na)        # size of the bin that receives
    n_mov = np.where(dst - src >= T, 0,                               # case 1
            np.where(src + dst < T, src,                              # case 2
                     -((-(src - dst + T)) // 2)))                     # eq. 6.1.7
    n_mov = np.minimum(n_mov, src)

    # eq. 6.1.5: new radius rho_min^{k+1} + delta / n*, n* the least n >= 3
    # with rho_min^{k+1} + delta/n < rho_max^{k+1}; mirrored for w = +1:
    # rho_max^k - delta / n*, n* least n >= 3 with rho_max^k - delta/n >
    # rho_min^k.  Fallbacks (not in the thesis): empty receiving bin ->
    # its range edges are used; single-valued bin -> the far edge is used.
    recv = np.where(w < 0, b, a)
    nr = cnt[recv]
    has = nr > 0
    lo_el = np.where(has, rs[np.minimum(starts[recv], N - 1)], edges[recv])
    hi_el = np.where(has, rs[np.maximum(ends[recv] - 1, 0)], edges[recv + 1])
    flat = hi_el <= lo_el
    lo_el = np.where(flat & (w > 0), edges[recv], lo_el)
    hi_el = np.where(flat & (w < 0), edges[recv + 1], hi_el)
    spread = hi_el - lo_el
    n_star = np.maximum(3, np.floor(d / spread).astype(np.int64) + 1)
    target = np.where(w < 0, lo_el + d / n_star, hi_el - d / n_star)

    # which sorted positions move: largest of B_k (w=-1) / smallest of B_k+1
    first = np.where(w < 0, ends[a] - n_mov, starts[b])
    pos = _ranges(first, n_mov)
    rho_new = rho.copy()
    rho_new[order[pos]] = np.repeat(target, n_mov)
    V_new = _radial_rescale(V, o, rho, rho_new)

    info = {
        "method": "yang_radial",
        "K": K,
        "n_thr": T,
        "origin": o,
        "rho_min": rmin,
        "rho_max": float(edges[-1]),
        "pairs": a,
        "n_mov": n_mov,
        "moved_vertices": int(n_mov.sum()),
        "counts_before": cnt,
        "capacity": int(len(emb)),
    }
    return V_new, info


def yang_radial_extract(V, n_bits, K=400, origin_mode="axis"):
    """Section 6.2: recompute origin and histogram from the marked mesh,
    take the embeddable pairs (eq. 6.2.8) in order and decode eq. 6.2.10."""
    V = np.asarray(V, dtype=np.float64)
    o = yang_origin(V, origin_mode)
    rho = np.linalg.norm(V - o, axis=1)
    idx, _, _, _ = _yang_hist(rho, K)
    cnt = np.bincount(idx, minlength=K)
    pairs = yang_pairs(K)
    emb = pairs[(cnt[pairs] + cnt[pairs + 1]) >= 1]
    a = emb[:n_bits]
    bits = (cnt[a + 1] < cnt[a]).astype(np.int64)        # eq. 6.2.10
    if len(bits) < n_bits:
        bits = np.concatenate([bits, np.zeros(n_bits - len(bits), np.int64)])
    return bits, {"origin": o, "counts": cnt, "pairs": a}


# ---------------------------------------------------------------------------
# Yang 2013, section 6.4: specific steganalyzer against Cho's Method I
# ---------------------------------------------------------------------------

def bhattacharyya_gauss(mu1, var1, mu2, var2):
    """Eq. 6.4.14: Bhattacharyya distance of two 1-D Gaussians."""
    s = 0.5 * (var1 + var2)
    return (0.125 * (mu2 - mu1) ** 2 / s
            + 0.5 * math.log(s / math.sqrt(var1 * var2)))


def cho_bin_means(V, K, center=None):
    """Eq. 6.4.13: mean of the bin-normalised norms of every non-empty bin
    (Cho's binning and normalisation, see cho_bins)."""
    V = np.asarray(V, dtype=np.float64)
    o = cho_center(V) if center is None else center
    rho = np.linalg.norm(V - o, axis=1)
    idx, x, _, _ = cho_bins(rho, K)
    st, c = _cho_stat(x, idx, K, np.ones(K), "mean")
    return st[c > 0]


def cho_steganalysis(V, K_min=1, K_max=500, eps=0.15, eps2=0.03,
                     min_bins=8, reg_covar=1e-6, random_state=0):
    """Specific steganalysis of Cho's mean method (section 6.4).

    For every K in [K_min, K_max]: bin means m_k (eq. 6.4.13), 2-component
    Gaussian mixture (sklearn GaussianMixture, 1-D), separation D_K
    (eq. 6.4.14); K' = argmax D_K (eq. 6.4.15); then "marked" iff
    eq. 6.4.16 (min C > 0.5 > max C~ and |min C + max C~ - 1| <= eps) and
    eq. 6.4.17 (| |C| - |C~| | / K' <= eps2) both hold, C being the cluster
    with the larger mean.

    Not in the thesis (documented in docs/radial.md): K with fewer than
    `min_bins` non-empty bins, or a fit that leaves a component with fewer
    than 2 bins, gets D_K = -inf (with 2-4 points a 2-Gaussian fit is
    degenerate and D_K explodes, which would always give K' <= 3)."""
    from sklearn.mixture import GaussianMixture

    t0 = time.perf_counter()
    V = np.asarray(V, dtype=np.float64)
    o = cho_center(V)
    rho = np.linalg.norm(V - o, axis=1)
    Ks = np.arange(K_min, K_max + 1)
    D = np.full(len(Ks), -np.inf)
    fits = {}
    for j, K in enumerate(Ks):
        idx, x, _, _ = cho_bins(rho, int(K))
        st, c = _cho_stat(x, idx, int(K), np.ones(int(K)), "mean")
        m = st[c > 0]
        if len(m) < max(min_bins, 2):
            continue
        g = GaussianMixture(n_components=2, covariance_type="full",
                            reg_covar=reg_covar, random_state=random_state)
        lab = g.fit_predict(m.reshape(-1, 1))
        if np.bincount(lab, minlength=2).min() < 2:
            continue
        mu = g.means_.ravel()
        var = g.covariances_.ravel()
        D[j] = bhattacharyya_gauss(mu[0], var[0], mu[1], var[1])
        fits[int(K)] = (m, lab, mu)
    j = int(np.argmax(D))
    Kp = int(Ks[j])
    m, lab, mu = fits[Kp]
    hi = int(np.argmax(mu))
    C, Ct = m[lab == hi], m[lab != hi]
    c_min, ct_max = float(C.min()), float(Ct.max())
    cond16 = (c_min > 0.5 > ct_max) and abs(c_min + ct_max - 1.0) <= eps
    balance = abs(len(C) - len(Ct)) / Kp
    cond17 = balance <= eps2
    return {
        "K_est": Kp,
        "D_max": float(D[j]),
        "D": D,
        "Ks": Ks,
        "min_C": c_min,
        "max_Ctilde": ct_max,
        "size_C": int(len(C)),
        "size_Ctilde": int(len(Ct)),
        "eq_6_4_16": bool(cond16),
        "eq_6_4_17": bool(cond17),
        "balance": float(balance),
        "marked": bool(cond16 and cond17),
        "seconds": time.perf_counter() - t0,
    }
