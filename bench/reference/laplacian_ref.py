"""Reference (numpy + scipy.sparse) implementation of the Laplacian-coordinate
histogram watermark of Y. Yang, PhD thesis 2013, Chapter 7 (thesis text lines
1589-1944 of /work/shared/reference/yang-thesis-2013.txt).

Faithful defaults reproduce the thesis; every option that departs from it is
OFF by default and marked "BEYOND THE THESIS". Interpretation choices are
tagged "[I#]" and listed (with thesis line numbers) in docs/laplacian.md.

Conventions
-----------
* Bits are given / returned as 0/1 integers; bit 1 <-> w_j = +1, bit 0 <-> w_j = -1.
* Bins are 0-based in code: code bin b == thesis bin B_{b+1}.
  Pair p (0-based, p = 0 .. P-1) is thesis pair (B_{2p+2}, B_{2p+3}) == code bins (2p+1, 2p+2).
* No Python loops over vertices, edges, bins or pairs (per-bin arrays are used).
  The only Python-level loop is over polygons in edges_from_faces(polys=...), used
  only for non-triangle meshes.
"""
import math
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu
from scipy.sparse.csgraph import connected_components

EPS_DEFAULT = 1e-5   # thesis line 1811: "epsilon ... is fixed at 0.00001"
N_C = 70             # thesis line 1843: K = ceil(N / N_c), N_c = 70
N_THR_DEFAULT = 46   # thesis line 1843 / Table 7.1
N_ROBUST_DEFAULT = 5  # Table 7.1


# ---------------------------------------------------------------------------
# Mesh graph / Kirchhoff matrix
# ---------------------------------------------------------------------------
def edges_from_faces(F, polys=None):
    """Unique undirected edges (i<j) of the mesh, eq. 7.1.1 (E).

    F: (m,3) triangles. If `polys` (list of index arrays, e.g. quads) is given the
    polygon boundary edges are used instead (no fan diagonals)."""
    if polys is not None:
        E = np.concatenate([np.stack([p, np.roll(p, -1)], 1) for p in polys])  # loop over faces only
    else:
        F = np.asarray(F, dtype=np.int64)
        E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E = np.sort(E, axis=1)
    E = E[E[:, 0] != E[:, 1]]                 # drop degenerate (repeated-index) face edges
    return np.unique(E, axis=0)


def kirchhoff(n, F, eps=EPS_DEFAULT, edges=None, polys=None):
    """Regularised Kirchhoff matrix M (csc), eq. 7.1.3 then eq. 7.1.4.

    M_ii = |N(v_i)| - eps, M_ij = -1 for (i,j) in E, 0 otherwise.
    The degree |N(v_i)| is the number of distinct edge-neighbours (duplicate
    edges shared by two faces count once) [I1].

    Solvability: K = D - A is singular with one null vector (the constant) per
    connected component, and an unreferenced vertex is a 1x1 zero block. The
    "- eps" of eq. 7.1.4 shifts every eigenvalue lambda of K to lambda - eps, so M
    is nonsingular as long as eps is not an eigenvalue of K: every null mode
    becomes -eps (an isolated vertex row is just [-eps]), and eps = 1e-5 is far
    below the smallest non-zero eigenvalue (Fiedler value) of the test meshes
    (checked in check_laplacian_ref.py). M is therefore symmetric INDEFINITE
    (one negative eigenvalue per component): use LU (splu) or pivoted LDL^T,
    not Cholesky [I2]. eps = 0 returns the plain Kirchhoff matrix (singular).
    """
    E = edges_from_faces(F, polys) if edges is None else np.asarray(edges)
    deg = np.bincount(E.ravel(), minlength=n).astype(np.float64)          # |N(v_i)|, eq. 7.1.3
    rows = np.concatenate([E[:, 0], E[:, 1], np.arange(n)])
    cols = np.concatenate([E[:, 1], E[:, 0], np.arange(n)])
    vals = np.concatenate([-np.ones(2 * len(E)), deg - eps])              # eq. 7.1.3 / eq. 7.1.4
    return sp.csc_matrix((vals, (rows, cols)), shape=(n, n))


def laplacian_coords(V, F, eps=EPS_DEFAULT, M=None, polys=None):
    """L = M X, eq. 7.1.2, with M regularised by eq. 7.1.4 (thesis line 1780
    says extraction uses "Eq. 7.1.3 and Eq. 7.1.4") [I3].
    Pass eps=0 for the pure Kirchhoff Laplacian (exactly translation invariant)."""
    if M is None:
        M = kirchhoff(len(V), F, eps, polys=polys)
    return M @ np.asarray(V, dtype=np.float64)


def laplacian_lengths(V, F, eps=EPS_DEFAULT, M=None, polys=None):
    """d_i = ||L_i||, eq. 7.1.5 (with L from eq. 7.1.2)."""
    return np.linalg.norm(laplacian_coords(V, F, eps, M, polys), axis=1)


# ---------------------------------------------------------------------------
# Scale helpers (BEYOND THE THESIS, for side-info normalisation)
# ---------------------------------------------------------------------------
def mean_edge_length(V, F, polys=None):
    E = edges_from_faces(F, polys)
    return float(np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1).mean())


def bbox_diag(V):
    return float(np.linalg.norm(V.max(0) - V.min(0)))


def scale_of(V, F, how, polys=None):
    if how is None:
        return 1.0
    if how == "mean_edge":
        return mean_edge_length(V, F, polys)
    if how == "bbox":
        return bbox_diag(V)
    if how == "rms":   # RMS distance to centroid
        return float(np.sqrt(((V - V.mean(0)) ** 2).sum(1).mean()))
    if how.startswith("median_d"):   # median Laplacian length; "median_d:<lap_eps>"
        e = float(how.split(":")[1]) if ":" in how else EPS_DEFAULT
        return float(np.median(laplacian_lengths(V, F, e, polys=polys)))
    raise ValueError(how)


# ---------------------------------------------------------------------------
# Histogram / pairs
# ---------------------------------------------------------------------------
def default_K(N):
    return int(math.ceil(N / N_C))   # thesis line 1843, K = ceil(N/N_c)


def n_pairs(K):
    """(K_hat - 1)/2 candidate pairs, K_hat = 2 floor((K-2)/2) + 1, eq. 7.2.12."""
    K_hat = 2 * ((K - 2) // 2) + 1
    return (K_hat - 1) // 2


def bin_index(d, d_min, d_max, K):
    """0-based bin index of each d by eq. 7.1.6/7.1.7; -1 if d outside [d_min, d_max].

    Canonical formula (the C++ port must use the same, in double):
        delta = (d_max - d_min) / K ;  b = floor((d - d_min) / delta), clamped to K-1
    The clamp implements "d_max in B_K" (thesis line 1656) [I4]."""
    delta = (d_max - d_min) / K                                         # eq. 7.1.7
    inside = (d >= d_min) & (d <= d_max)
    with np.errstate(invalid="ignore", divide="ignore"):
        b = np.floor((d - d_min) / delta)                               # eq. 7.1.6
    b = np.where(inside, np.clip(b, 0, K - 1), -1).astype(np.int64)
    return b


def pair_counts(b, K):
    """Per-pair counts (|B_k|, |B_{k+1}|) for the (K_hat-1)/2 candidate pairs (eq. 7.2.12)."""
    c = np.bincount(b[b >= 0], minlength=K)
    P = n_pairs(K)
    lo = c[1:2 * P + 1:2]          # thesis B_2, B_4, ..., B_{K_hat-1}
    hi = c[2:2 * P + 2:2]          # thesis B_3, B_5, ..., B_{K_hat}
    return c, lo, hi


# ---------------------------------------------------------------------------
# Capacity
# ---------------------------------------------------------------------------
def capacity(V, F, K=None, n_thr=N_THR_DEFAULT, eps=EPS_DEFAULT, polys=None, d=None):
    """Number of valid pairs: f(B_k, B_{k+1}) = |B_k| + |B_{k+1}| >= n_thr (eq. 7.1.8)
    over the candidate pairs (B_2,B_3), ..., (B_{K_hat-1}, B_{K_hat}) (eq. 7.2.12)."""
    if d is None:
        d = laplacian_lengths(V, F, eps, polys=polys)
    K = default_K(len(d)) if K is None else int(K)
    b = bin_index(d, d.min(), d.max(), K)
    _, lo, hi = pair_counts(b, K)
    return int(np.count_nonzero(lo + hi >= n_thr))


# ---------------------------------------------------------------------------
# Embedding
# ---------------------------------------------------------------------------
def _component_labels(n, F, polys=None):
    E = edges_from_faces(F, polys)
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n))
    return connected_components(A, directed=False)[1]


def _recentre(Xh, X, labels):
    """Translate each connected component of Xh so that its centroid equals that of X."""
    ncomp = labels.max() + 1
    cnt = np.bincount(labels, minlength=ncomp)[:, None]
    sh = np.stack([np.bincount(labels, (X - Xh)[:, j], ncomp) for j in range(3)], 1) / cnt
    return Xh + sh[labels]


def compute_dhat(d, K, w, n_thr, n_robust, d_min=None, d_max=None, margin_always=False,
                 min_f=None):
    """Eq. 7.2.12-7.2.16: modified lengths d_hat carrying the +-1 bits w.

    Returns d_hat, used_pairs (pair indices carrying w, in order), info.
    margin_always (BEYOND THE THESIS): also apply the eq. 7.2.16 margin in "Case 1"
    (pairs already in the right order but with a smaller margin than Case 2 would give).
    min_f (BEYOND): only use pairs with f >= min_f (>= n_thr) as carriers.
    """
    d_min = d.min() if d_min is None else d_min
    d_max = d.max() if d_max is None else d_max
    delta = (d_max - d_min) / K                                          # eq. 7.1.7
    b = bin_index(d, d_min, d_max, K)                                   # eq. 7.1.6
    c, lo, hi = pair_counts(b, K)
    f = lo + hi                                                          # eq. 7.1.8
    P = n_pairs(K)
    valid = f >= (n_thr if min_f is None else max(n_thr, min_f))         # eq. 7.1.8 / 7.2 text l.1711
    vidx = np.flatnonzero(valid)
    nb = len(w)
    if nb > len(vidx):
        raise ValueError("message has %d bits, capacity is %d" % (nb, len(vidx)))
    used = vidx[:nb]                       # bits go sequentially into the valid pairs [I6]
    wp = np.zeros(P, np.int64)
    wp[used] = w

    # Target number of elements that must end up in the "losing" bin (eq. 7.2.16):
    # n = |B_src| - floor((f-1)/2) + floor((f-1)/n_robust)  =>  |B_src_hat| = floor((f-1)/2) - floor((f-1)/n_robust)
    keep = (f - 1) // 2 - (f - 1) // n_robust                            # eq. 7.2.16
    # Case 2 for w=+1: |B_k| < |B_{k+1}| -> move smallest of B_{k+1} down (eq. 7.2.13/14)
    up = (wp == +1) & (lo < hi)
    # Case 2 for w=-1 (the "completely analogous" case, thesis l.1713) [I5]:
    # |B_k| >= |B_{k+1}| -> move largest of B_k up into B_{k+1}
    dn = (wp == -1) & (lo >= hi)
    if margin_always:   # BEYOND THE THESIS: enforce the eq. 7.2.16 margin also in Case 1
        up |= (wp == +1) & (hi > keep)
        dn |= (wp == -1) & (lo > keep)
    n_up = np.where(up, np.minimum(np.maximum(hi - keep, 0), hi), 0)  # eq. 7.2.16 (+ "transfer all" clamp, l.1746)
    n_dn = np.where(dn, np.minimum(np.maximum(lo - keep, 0), lo), 0)

    # bin means of the ORIGINAL d (eq. 7.2.15); empty bin -> centre of the bin
    s = np.bincount(b[b >= 0], weights=d[b >= 0], minlength=K)
    centre = d_min + delta * (np.arange(K) + 0.5)                        # eq. 7.2.15, |B_k| = 0 case
    mean = np.where(c > 0, s / np.maximum(c, 1), centre)                 # eq. 7.2.15

    # per-bin instructions: move the n smallest of code bin 2p+2 to mean[2p+1] (w=+1),
    # or the n largest of code bin 2p+1 to mean[2p+2] (w=-1)
    low_n = np.zeros(K, np.int64)    # number of smallest elements to move out of this bin
    high_n = np.zeros(K, np.int64)   # number of largest elements to move out of this bin
    low_tgt = np.zeros(K)
    high_tgt = np.zeros(K)
    pk = np.arange(P)
    low_n[2 * pk + 2] = n_up
    low_tgt[2 * pk + 2] = mean[2 * pk + 1]
    high_n[2 * pk + 1] = n_dn
    high_tgt[2 * pk + 1] = mean[2 * pk + 2]

    # rank of each element inside its bin, ascending d, ties by vertex index (eq. 7.2.13) [I7]
    order = np.lexsort((np.arange(len(d)), d, b))
    rank = np.empty(len(d), np.int64)
    bs = b[order]
    start = np.searchsorted(bs, bs, side="left")
    rank[order] = np.arange(len(d)) - start
    bb = np.where(b >= 0, b, 0)
    inb = b >= 0
    mv_low = inb & (rank < low_n[bb])
    mv_high = inb & (rank >= c[bb] - high_n[bb])
    dhat = d.copy()
    dhat[mv_low] = low_tgt[bb[mv_low]]                                   # eq. 7.2.14
    dhat[mv_high] = high_tgt[bb[mv_high]]
    info = dict(n_moved=int(mv_low.sum() + mv_high.sum()), n_pairs_changed=int(up.sum() + dn.sum()),
                f=f, lo=lo, hi=hi, valid=valid, delta=delta)
    return dhat, used, info


def choose_n_thr(f, n_min=N_THR_DEFAULT, n_bits=0, search=64):
    """BEYOND THE THESIS (fix (e), blind variant): pick the embedding threshold in
    [n_min, n_min+search) that maximises the gap g = min_p dist(f_p, threshold
    boundary) so that no candidate pair is close to becoming valid/invalid.
    A pair is at distance f-n from validity if f >= n, and n-1-f if f < n.
    Ties -> smallest threshold. The chosen value must be passed to the extractor
    (the thesis already requires n_thr to be passed, l.1815). Returns (n_thr, gap)."""
    cand = np.arange(n_min, n_min + search)
    f = np.asarray(f)[None, :]
    n = cand[:, None]
    dist = np.where(f >= n, f - n, n - 1 - f)
    gap = dist.min(1)
    capok = (f >= n).sum(1) >= n_bits
    gap = np.where(capok, gap, -1)
    i = int(np.argmax(gap))
    return int(cand[i]), int(gap[i])


def _grounded_solve(Kmat, R, labels):
    """BEYOND THE THESIS (fix (d)): exact solve of K dX = R_proj without eps.

    R is projected to zero mean per connected component (the part of R that no
    dX can realise through K), one vertex per component is pinned (grounded
    Kirchhoff matrix: SPD, Cholesky-able), and dX is shifted to zero mean per
    component (centroid preserved). Then K dX == R_proj exactly (up to round-off)."""
    n = Kmat.shape[0]
    ncomp = labels.max() + 1
    cnt = np.bincount(labels, minlength=ncomp)[:, None]
    Rm = np.stack([np.bincount(labels, R[:, j], ncomp) for j in range(3)], 1) / cnt
    Rp = R - Rm[labels]
    first = np.full(ncomp, n)
    np.minimum.at(first, labels, np.arange(n))
    keep = np.ones(n, bool)
    keep[first] = False
    Kr = Kmat[keep][:, keep].tocsc()
    dX = np.zeros_like(R)
    if keep.any():
        dX[keep] = splu(Kr).solve(Rp[keep])
    dXm = np.stack([np.bincount(labels, dX[:, j], ncomp) for j in range(3)], 1) / cnt
    return dX - dXm[labels], Rm


def embed(V, F, bits, K=None, n_thr=N_THR_DEFAULT, n_robust=N_ROBUST_DEFAULT, eps=EPS_DEFAULT,
          polys=None, lap_eps=None, solve="full", recentre=None, margin_always=False,
          scale_norm=None, min_f=None, auto_thr=False, zero_sum=False):
    """Embed `bits` (0/1 array, len <= capacity) and return (V_marked, side_info).

    Thesis pipeline: L = M X (7.1.2, 7.1.4) -> d (7.1.5) -> bins (7.1.6/7) -> valid pairs
    (7.1.8, 7.2.12) -> d_hat (7.2.13-16) -> L_hat by radial projection (7.2.17-19)
    -> X_hat = M^{-1} L_hat (one sparse LU solve, thesis l.1772).

    BEYOND THE THESIS options (defaults = thesis):
      lap_eps         : eps used to compute L and d (default = eps, thesis [I3]);
                        0 -> pure Kirchhoff Laplacian, exactly translation invariant
      solve="delta"   : X_hat = X + M^{-1}(L_hat - L)   (same maths, less round-off;
                        required when lap_eps != eps)
      solve="grounded": eps-free exact solve (_grounded_solve), centroid kept
      recentre="component"|"global" : translate X_hat so each component's centroid
                        equals the original one (kills the eps-mode translation)
      margin_always   : enforce eq. 7.2.16 margin in Case 1 too
      scale_norm      : "mean_edge" | "bbox" | "rms" | "median_d" -> also store d_min, d_max
                        divided by that scale of the marked mesh (d_min_rel, d_max_rel)
      min_f           : only pairs with f >= min_f carry bits
      auto_thr        : choose n_thr >= given n_thr with choose_n_thr (stored in side_info)
      zero_sum        : (fix (d)) subtract, per connected component, the mean of
                        L_hat - L over the CHANGED rows from those rows, so that
                        sum_i (L_hat_i - L_i) = 0 per component. Then M^{-1} adds no
                        translation (1^T M dX = -eps 1^T dX = 0) and the grounded
                        solve needs no projection; unchanged rows stay exact.
    """
    X = np.asarray(V, dtype=np.float64)
    N = len(X)
    K = default_K(N) if K is None else int(K)
    lap_eps = eps if lap_eps is None else lap_eps
    Kl = kirchhoff(N, F, lap_eps, polys=polys)                            # eq. 7.1.3 + 7.1.4
    L = Kl @ X                                                            # eq. 7.1.2
    d = np.linalg.norm(L, axis=1)                                         # eq. 7.1.5
    d_min, d_max = float(d.min()), float(d.max())
    w = 2 * np.asarray(bits, dtype=np.int64) - 1
    gap = None
    if auto_thr:
        b0 = bin_index(d, d_min, d_max, K)
        _, lo0, hi0 = pair_counts(b0, K)
        n_thr, gap = choose_n_thr(lo0 + hi0, n_thr, len(w))
    dhat, used, inf = compute_dhat(d, K, w, n_thr, n_robust, d_min, d_max, margin_always, min_f)
    # eq. 7.2.19: L_hat_i = L_i * d_hat_i / d_i  (only changed rows; d_i > 0 for them
    # because B_1, which holds d_min, is never modified)
    ch = dhat != d
    Lh = L.copy()
    Lh[ch] = L[ch] * (dhat[ch] / d[ch])[:, None]                          # eq. 7.2.19
    zs_err = 0.0
    if zero_sum and ch.any():   # BEYOND THE THESIS, fix (d)
        labels = _component_labels(N, F, polys)
        ncomp = labels.max() + 1
        nch = np.bincount(labels[ch], minlength=ncomp)
        for it in range(8):   # alternate: zero-sum projection <-> restore lengths d_hat (8 fixed passes)
            if it:
                Lh[ch] *= (dhat[ch] / np.linalg.norm(Lh[ch], axis=1))[:, None]
            R = Lh - L
            tot = np.stack([np.bincount(labels, R[:, j], ncomp) for j in range(3)], 1)
            Lh[ch] -= (tot / np.maximum(nch, 1)[:, None])[labels[ch]]
        zs_err = float(np.abs(np.linalg.norm(Lh[ch], axis=1) - dhat[ch]).max() / inf["delta"])
    if solve == "full":
        if lap_eps != eps:
            raise ValueError("solve='full' needs lap_eps == eps (use 'delta' or 'grounded')")
        Xh = splu(kirchhoff(N, F, eps, polys=polys)).solve(Lh)            # X_hat = M^{-1} L_hat (l.1772) [I2]
    elif solve == "delta":
        Xh = X + splu(kirchhoff(N, F, eps, polys=polys)).solve(Lh - L)
    elif solve == "grounded":
        labels = _component_labels(N, F, polys)
        dX, _ = _grounded_solve(kirchhoff(N, F, 0.0, polys=polys), Lh - L, labels)
        Xh = X + dX
    else:
        raise ValueError(solve)
    if recentre is not None:
        labels = (_component_labels(N, F, polys) if recentre == "component"
                  else np.zeros(N, np.int64))
        Xh = _recentre(Xh, X, labels)
    side = dict(K=K, n_thr=n_thr, n_robust=n_robust, eps=eps, lap_eps=lap_eps, d_min=d_min, d_max=d_max,
                n_bits=len(w), pairs=used.copy(), capacity=int(inf["valid"].sum()), thr_gap=gap,
                n_moved=inf["n_moved"], n_pairs_changed=inf["n_pairs_changed"], delta=inf["delta"],
                zero_sum_dev=zs_err)
    if scale_norm is not None:
        if scale_norm == "median_d":
            scale_norm = "median_d:%r" % lap_eps
        s = scale_of(Xh, F, scale_norm, polys)     # measured on the MARKED mesh (what the extractor sees)
        side.update(scale_norm=scale_norm, d_min_rel=d_min / s, d_max_rel=d_max / s)
    return Xh, side


def range_factor_scores(d, d_min, d_max, K, pairs, factors):
    """BEYOND THE THESIS (fix (c)): for each candidate factor t, bin d with the range
    [t*d_min, t*d_max] and score the alignment by the mean relative margin
    |lo - hi| / (lo + hi) over the stored carrier pairs (embedding leaves large
    margins there, a mis-scaled grid does not). Vectorised with searchsorted."""
    ds = np.sort(d)
    delta = (d_max - d_min) / K
    pairs = np.asarray(pairs)
    # edges of code bins 2p+1, 2p+2 (and the end of 2p+2): lo-bin = [e0, e1), hi-bin = [e1, e2)
    e = d_min + delta * np.stack([2 * pairs + 1, 2 * pairs + 2, 2 * pairs + 3], 1)   # (P, 3)
    E = np.asarray(factors)[:, None, None] * e[None]                                  # (T, P, 3)
    idx = np.searchsorted(ds, E.ravel(), side="left").reshape(E.shape)
    lo = idx[..., 1] - idx[..., 0]
    hi = idx[..., 2] - idx[..., 1]
    return (np.abs(lo - hi) / np.maximum(lo + hi, 1)).mean(1)


# ---------------------------------------------------------------------------
# Extraction
# ---------------------------------------------------------------------------
def extract(V, F, side_info=None, n_bits=None, K=None, n_thr=N_THR_DEFAULT, eps=EPS_DEFAULT,
            polys=None, use_side_range=True, keyed_pairs=False, pairs=None, resync_count=False,
            range_search=None, return_details=False):
    """Blind extraction (thesis §7.3, eq. 7.3.20, 7.3.21 and the rule after it).

    * side_info None: K (default ceil(N/70)) and n_thr as given; d_min/d_max are
      taken from the marked mesh itself (thesis l.1786).
    * side_info given: K, n_thr, n_bits from it; if use_side_range, bins are
      formed only from d_hat within [d_min, d_max] of side_info (thesis l.1786,
      "we form the bins using only those d_i that satisfy d_min <= d_i <= d_max").
      If side_info has "scale_norm" (BEYOND), d_min/d_max are rescaled by the
      attacked mesh's own scale: d_min = d_min_rel * scale(V).
    * keyed_pairs (BEYOND): read bits from side_info["pairs"] instead of
      re-detecting valid pairs with eq. 7.3.21; `pairs` = explicit pair list.
    * use_side_range=False with side_info: blind range (d_hat_min, d_hat_max of the
      mesh) but K, n_thr, n_bits, lap_eps from side_info.
    * range_search=(t_lo, t_hi, n) (BEYOND, needs side_info["pairs"]): multiply the
      (stored / normalised / blind) range by the factor t in geomspace(t_lo, t_hi, n)
      that maximises range_factor_scores, then decode.
    * resync_count (BEYOND): if the number of pairs with f >= n_thr differs from
      n_bits, drop/add the pairs nearest to the threshold until it matches.
    * eps: eps used to compute L / d when no side_info (pass 0 for the pure
      Kirchhoff Laplacian); with side_info its "lap_eps" is used.
    Returns 0/1 bits (eq. after 7.3.21: +1 if |B_k| >= |B_{k+1}|).
    """
    X = np.asarray(V, dtype=np.float64)
    N = len(X)
    lap_eps = eps if side_info is None else side_info.get("lap_eps", side_info.get("eps", eps))
    d = laplacian_lengths(X, F, lap_eps, polys=polys)              # eq. 7.1.2-7.1.5 (l.1780)
    if side_info is not None:
        K = side_info["K"]
        n_thr = side_info["n_thr"]
        n_bits = side_info.get("n_bits") if n_bits is None else n_bits
    K = default_K(N) if K is None else int(K)
    if side_info is not None and use_side_range:
        if "scale_norm" in side_info:
            s = scale_of(X, F, side_info["scale_norm"], polys)
            d_min, d_max = side_info["d_min_rel"] * s, side_info["d_max_rel"] * s
        else:
            d_min, d_max = side_info["d_min"], side_info["d_max"]
    else:
        d_min, d_max = float(d.min()), float(d.max())
    t_best = 1.0
    if range_search is not None:   # BEYOND THE THESIS: refine the range by a factor search
        lo_t, hi_t, n_t = range_search
        fac = np.geomspace(lo_t, hi_t, int(n_t))
        sc = range_factor_scores(d, d_min, d_max, K, side_info["pairs"], fac)
        t_best = float(fac[int(np.argmax(sc))])
        d_min, d_max = d_min * t_best, d_max * t_best
    b = bin_index(d, d_min, d_max, K)                  # eq. 7.1.6/7.1.7 (outside range -> ignored)
    _, lo, hi = pair_counts(b, K)                      # pairs (B_2,B_3)..(B_Khat-1,B_Khat)
    f = lo + hi
    if pairs is not None:
        pidx = np.asarray(pairs)
    elif keyed_pairs:
        pidx = np.asarray(side_info["pairs"])
    else:
        pidx = np.flatnonzero(f >= n_thr)              # eq. 7.3.20 / 7.3.21
        if resync_count and n_bits is not None and len(pidx) != n_bits:
            # BEYOND THE THESIS (fix (e), needs only n_bits): drop the valid pairs whose f is
            # closest above n_thr, or add the invalid pairs whose f is closest below it,
            # until exactly n_bits pairs remain (ties -> lower pair index).
            P = len(f)
            if len(pidx) > n_bits:
                keep = pidx[np.lexsort((pidx, -f[pidx]))[:n_bits]]
            else:
                inv = np.setdiff1d(np.arange(P), pidx)
                add = inv[np.lexsort((inv, -f[inv]))[:n_bits - len(pidx)]]
                keep = np.concatenate([pidx, add])
            pidx = np.sort(keep)
    bits = (lo[pidx] >= hi[pidx]).astype(np.int64)     # +1 (bit 1) if |B_k| >= |B_{k+1}|
    if n_bits is not None:
        bits = bits[:n_bits]
    if return_details:
        return bits, dict(pairs=pidx, f=f, lo=lo, hi=hi, d_min=d_min, d_max=d_max, d=d, range_factor=t_best)
    return bits


def cdr(a, b):
    """Correct detection rate; missing trailing bits count as errors."""
    a = np.asarray(a)
    b = np.asarray(b)
    n = len(a)
    m = min(n, len(b))
    return float(np.count_nonzero(a[:m] == b[:m])) / max(n, 1)


def nc(a, b):
    """Normalised correlation of +-1 sequences (missing bits -> 0)."""
    a = 2 * np.asarray(a) - 1
    bb = np.zeros(len(a))
    m = min(len(a), len(b))
    bb[:m] = 2 * np.asarray(b)[:m] - 1
    da = a - a.mean()
    db = bb - bb.mean()
    den = np.sqrt((da ** 2).sum() * (db ** 2).sum())
    return float((da * db).sum() / den) if den > 0 else 0.0
