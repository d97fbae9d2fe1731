#include "meshmark/laplacian_watermark.h"
#include "meshmark/error.h"
#include "meshmark/laplacian_coordinates.h"

#include <Eigen/SparseCholesky>
#ifdef MESHMARK_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace meshmark {

LaplacianHistogram laplacian_histogram(const Eigen::Ref<const Eigen::VectorXd>& d, int K, double lo, double hi,
                                       const Eigen::Ref<const VectorXb>& mask) {
  if (K < 4) throw MeshError("the number of bins K must be at least 4, got " + std::to_string(K));
  if (!(hi > lo)) throw MeshError("the Laplacian lengths span an empty range (all equal?): cannot form bins");
  LaplacianHistogram h;
  h.K = K;
  h.lo = lo;
  h.hi = hi;
  h.delta = (hi - lo) / K;  // eq. 7.1.7
  h.bin = VectorXi::Constant(d.size(), -1);
  h.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (!mask[i] || !(d[i] >= lo && d[i] <= hi)) continue;  // §7.3: only d within [d_min, d_max]
    int k = static_cast<int>(std::floor((d[i] - lo) / h.delta));  // eq. 7.1.6
    k = std::min(std::max(k, 0), K - 1);                          // d_max belongs to B_K
    h.bin[i] = k;
    ++h.counts[k];
  }
  return h;
}

std::vector<int> valid_pairs(const LaplacianHistogram& h, int n_thr) {
  std::vector<int> out;
  for (int j = 0; j < h.n_pairs(); ++j)
    if (h.pair_size(j) >= n_thr && h.pair_size(j) > 0) out.push_back(j);  // eq. 7.1.8
  return out;
}

namespace {

// Per-component labels of the edge graph by breadth-first search over the CSR adjacency; `order`
// (if given) receives the vertices in visiting order, a numbering whose neighbours lie close together.
VectorXi component_labels(const Adjacency& A, Index n, Index& count, std::vector<Index>* order = nullptr) {
  VectorXi label = VectorXi::Constant(n, -1);
  std::vector<Index> queue;
  queue.reserve(static_cast<size_t>(n));
  count = 0;
  for (Index s = 0; s < n; ++s) {
    if (label[s] >= 0) continue;
    label[s] = count;
    size_t head = queue.size();
    queue.push_back(s);
    while (head < queue.size()) {
      const Index v = queue[head++];
      for (Offset k = A.ptr[v]; k < A.ptr[v + 1]; ++k)
        if (label[A.nbr[k]] < 0) {
          label[A.nbr[k]] = count;
          queue.push_back(A.nbr[k]);
        }
    }
    ++count;
  }
  if (order) *order = std::move(queue);
  return label;
}

// The adjacency renumbered by `order` (new vertex k is old vertex order[k]); neighbour lists unsorted.
Adjacency permute_adjacency(const Adjacency& A, const std::vector<Index>& order, const std::vector<Index>& inv) {
  const Index n = static_cast<Index>(order.size());
  Adjacency P;
  P.ptr.resize(n + 1);
  P.ptr[0] = 0;
  for (Index k = 0; k < n; ++k) P.ptr[k + 1] = P.ptr[k] + (A.ptr[order[k] + 1] - A.ptr[order[k]]);
  P.nbr.resize(A.nbr.size());
  for (Index k = 0; k < n; ++k) {
    Offset o = P.ptr[k];
    for (Offset j = A.ptr[order[k]]; j < A.ptr[order[k] + 1]; ++j) P.nbr[o++] = inv[A.nbr[j]];
  }
  return P;
}

// Solves M X = B for an (n,3) right-hand side. SPD systems use CHOLMOD's supernodal Cholesky when
// meshmark was built with it, else Eigen's simplicial LDL^T (also used for the indefinite thesis system).
MatrixX3dR solve(const Eigen::SparseMatrix<double>& M, const MatrixX3dR& B, bool spd) {
  Eigen::MatrixXd rhs = B;  // column-major for the solvers
  Eigen::MatrixXd X;
#ifdef MESHMARK_HAVE_CHOLMOD
  if (spd) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> chol;
    // One ordering, AMD: METIS' nested dissection needs a third fewer flops to factorise, but on
    // 1.28M vertices computing it took 10 s against AMD's 2 s, more than it saves (8.5 s vs 13.8 s).
    chol.cholmod().nmethods = 1;
    chol.cholmod().method[0].ordering = CHOLMOD_AMD;
    chol.compute(M);
    if (chol.info() == Eigen::Success) {
      X = chol.solve(rhs);
      if (chol.info() == Eigen::Success) return X;
    }
  }
#endif
  (void)spd;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(M);
  if (ldlt.info() != Eigen::Success) throw MeshError("the Laplacian system could not be factorised");
  X = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success) throw MeshError("the Laplacian system could not be solved");
  return X;
}

// Kirchhoff matrix (eq. 7.1.3) assembled straight from the sorted CSR adjacency, with `shift`
// added to the diagonal (eq. 7.1.4 uses -eps).
Eigen::SparseMatrix<double> kirchhoff_matrix_shifted(const Adjacency& A, double shift) {
  const Index n = static_cast<Index>(A.ptr.size()) - 1;
  Eigen::SparseMatrix<double> M(n, n);
  M.resizeNonZeros(static_cast<Eigen::Index>(A.nbr.size()) + n);
  auto* outer = M.outerIndexPtr();
  auto* inner = M.innerIndexPtr();
  double* val = M.valuePtr();
  Eigen::Index k = 0;
  for (Index i = 0; i < n; ++i) {
    outer[i] = static_cast<int>(k);
    const Offset b = A.ptr[i], e = A.ptr[i + 1];
    Offset j = b;
    for (; j < e && A.nbr[j] < i; ++j, ++k) inner[k] = A.nbr[j], val[k] = -1.0;
    inner[k] = i, val[k] = static_cast<double>(e - b) + shift, ++k;
    for (; j < e; ++j, ++k) inner[k] = A.nbr[j], val[k] = -1.0;
  }
  outer[n] = static_cast<int>(k);
  return M;
}

// The bins' members in ascending order of d (eq. 7.2.13), as CSR over the bins.
struct BinMembers {
  std::vector<Offset> start;
  std::vector<Index> members;
};

BinMembers bin_members(const LaplacianHistogram& hist) {
  BinMembers B;
  const Index n = static_cast<Index>(hist.bin.size());
  B.start.assign(static_cast<size_t>(hist.K) + 1, 0);
  for (Index i = 0; i < n; ++i)
    if (hist.bin[i] >= 0) ++B.start[hist.bin[i] + 1];
  for (int k = 0; k < hist.K; ++k) B.start[k + 1] += B.start[k];
  B.members.resize(static_cast<size_t>(B.start[hist.K]));
  std::vector<Offset> fill(B.start.begin(), B.start.end() - 1);
  for (Index i = 0; i < n; ++i)
    if (hist.bin[i] >= 0) B.members[fill[hist.bin[i]]++] = i;
  return B;
}

// Sets d_target for the elements each carrier pair moves (eqs. 7.2.13-7.2.16) and returns how many
// were moved. `short_pairs` counts the pairs that moved more than `tolerance(margin)` elements, i.e.
// whose histogram still lacks part of the margin the mark asks for.
struct Selection {
  int n_moved = 0;
  int short_pairs = 0;
};

Selection select_targets(const Eigen::VectorXd& d, const LaplacianHistogram& hist, const std::vector<int>& pairs,
                         const std::vector<int>& bits, const LaplacianEmbedOptions& opt, bool satisfied_only,
                         Eigen::VectorXd& d_target) {
  const BinMembers B = bin_members(hist);
  Selection S;
  for (size_t c = 0; c < pairs.size(); ++c) {
    const int j = pairs[c];
    if (j < 0 || j >= hist.n_pairs()) throw MeshError("pair index " + std::to_string(j) + " out of range");
    const int k1 = 2 * j + 1, k2 = 2 * j + 2;  // thesis bins B_{2j+2}, B_{2j+3}
    const int b = bits[c];
    const Offset n1 = B.start[k1 + 1] - B.start[k1], n2 = B.start[k2 + 1] - B.start[k2];
    const Offset f = n1 + n2;
    if (f == 0) continue;
    // The bin that must win: k1 for +1 (|B^k1| >= |B^k2|), k2 for -1 (eq. 7.1.9).
    const int win = b > 0 ? k1 : k2, lose = b > 0 ? k2 : k1;
    const Offset n_win = b > 0 ? n1 : n2, n_lose = f - n_win;
    const Offset margin = (f - 1) / opt.n_robust;
    // eq. 7.2.16: n = |B_lose| - floor((f-1)/2) + floor((f-1)/n_robust), at most |B_lose|.
    Offset n_move = n_lose - (f - 1) / 2 + margin;
    const bool satisfied = b > 0 ? n1 >= n2 : n1 < n2;
    if (satisfied_only && satisfied) n_move = 0;  // Case 1: no alteration (thesis)
    n_move = std::min(std::max<Offset>(n_move, 0), n_lose);
    if (n_move == 0) continue;
    // A later round of the iterative solve tops up a pair only when it lacks more than an eighth of
    // its margin (at least one element) or reads the wrong bit.
    if (!satisfied || n_move > std::max<Offset>(1, margin / 8)) ++S.short_pairs;
    // Target value (eq. 7.2.15): mean of the winning bin, or its centre when empty.
    const double lo_w = hist.lo + hist.delta * win;
    double dbar = lo_w + 0.5 * hist.delta;
    if (n_win > 0) {
      double s = 0;
      for (Offset m = B.start[win]; m < B.start[win + 1]; ++m) s += d[B.members[m]];
      dbar = s / static_cast<double>(n_win);
    }
    if (!opt.thesis_exact)  // keep moved lengths off the bin edges (float32/OBJ rounding)
      dbar = std::min(std::max(dbar, lo_w + 0.25 * hist.delta), lo_w + 0.75 * hist.delta);
    // Move the elements of the losing bin nearest to the winning one: the smallest of B_k2 for +1,
    // the largest of B_k1 for -1 (eqs. 7.2.13-7.2.14).
    std::vector<Index> lose_members(B.members.begin() + B.start[lose], B.members.begin() + B.start[lose + 1]);
    auto by_d = [&](Index a, Index c2) { return d[a] < d[c2] || (d[a] == d[c2] && a < c2); };
    if (b > 0)
      std::partial_sort(lose_members.begin(), lose_members.begin() + n_move, lose_members.end(), by_d);
    else
      std::partial_sort(lose_members.rbegin(), lose_members.rbegin() + n_move, lose_members.rend(),
                        [&](Index a, Index c2) { return by_d(c2, a); });
    for (Offset m = 0; m < n_move; ++m) {
      const Index i = b > 0 ? lose_members[m] : lose_members[lose_members.size() - 1 - m];
      d_target[i] = dbar;
      ++S.n_moved;
    }
  }
  return S;
}

// eq. 7.2.19: L^_i = L_i d^_i / d_i, as the change dL = L^ - L (zero where d is unchanged).
MatrixX3dR length_change(const MatrixX3dR& L, const Eigen::VectorXd& d, const Eigen::VectorXd& d_target) {
  const Index n = static_cast<Index>(L.rows());
  MatrixX3dR dL = MatrixX3dR::Zero(n, 3);
  for (Index i = 0; i < n; ++i)
    if (d_target[i] != d[i] && d[i] > 0) dL.row(i) = L.row(i) * (d_target[i] / d[i] - 1.0);
  return dL;
}

// The same for any carrier (laplacian_carrier.h): dL_i = direction_i gain_i (d^_i - d_i), the
// first-order change of L_i that takes s_i to d^_i (for the thesis carrier this is eq. 7.2.19).
MatrixX3dR carrier_change(const LaplacianCarrierField& F, const Eigen::VectorXd& d, const Eigen::VectorXd& d_target) {
  const Index n = static_cast<Index>(d.size());
  MatrixX3dR dL = MatrixX3dR::Zero(n, 3);
  for (Index i = 0; i < n; ++i)
    if (d_target[i] != d[i]) dL.row(i) = F.direction.row(i) * (F.gain[i] * (d_target[i] - d[i]));
  return dL;
}

// Jacobi-preconditioned conjugate gradients on (K + shift I) X = B for the Kirchhoff matrix K of the
// adjacency (eq. 7.1.3), applied without assembling it; each of the 3 columns is its own system.
// Starts from X = 0 and takes at most `iterations` steps (fewer once every column's residual is below
// 1e-10 of its right-hand side). Returns the number of steps taken. Fused loops: two passes over the
// rows per step.
int pcg(const Adjacency& A, double shift, const MatrixX3dR& B, int iterations, MatrixX3dR& X) {
  const Index n = static_cast<Index>(B.rows());
  std::vector<double> dinv(static_cast<size_t>(n));
  for (Index i = 0; i < n; ++i) dinv[i] = 1.0 / (static_cast<double>(A.ptr[i + 1] - A.ptr[i]) + shift);
  X.setZero(n, 3);
  MatrixX3dR R = B, P(n, 3), Q(n, 3);
  double rz[3] = {0, 0, 0}, bb[3] = {0, 0, 0};
  for (Index i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      P(i, c) = R(i, c) * dinv[i];
      rz[c] += R(i, c) * P(i, c);
      bb[c] += B(i, c) * B(i, c);
    }
  double rr[3] = {bb[0], bb[1], bb[2]};
  int it = 0;
  for (; it < iterations; ++it) {
    if (rr[0] <= 1e-20 * bb[0] && rr[1] <= 1e-20 * bb[1] && rr[2] <= 1e-20 * bb[2]) break;
    // Q = (K + shift I) P and the dot products P.Q
    double pq[3] = {0, 0, 0};
    for (Index i = 0; i < n; ++i) {
      const Offset b = A.ptr[i], e = A.ptr[i + 1];
      double s0 = 0, s1 = 0, s2 = 0;
      for (Offset k = b; k < e; ++k) {
        const Index j = A.nbr[k];
        s0 += P(j, 0);
        s1 += P(j, 1);
        s2 += P(j, 2);
      }
      const double g = static_cast<double>(e - b) + shift;
      Q(i, 0) = g * P(i, 0) - s0;
      Q(i, 1) = g * P(i, 1) - s1;
      Q(i, 2) = g * P(i, 2) - s2;
      pq[0] += P(i, 0) * Q(i, 0);
      pq[1] += P(i, 1) * Q(i, 1);
      pq[2] += P(i, 2) * Q(i, 2);
    }
    double alpha[3];
    for (int c = 0; c < 3; ++c) alpha[c] = pq[c] > 0 ? rz[c] / pq[c] : 0.0;
    // X += alpha P, R -= alpha Q, rz' = R.(D^-1 R)
    double rz_new[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) rr[c] = 0;
    for (Index i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        X(i, c) += alpha[c] * P(i, c);
        const double r = R(i, c) - alpha[c] * Q(i, c);
        R(i, c) = r;
        rz_new[c] += r * r * dinv[i];
        rr[c] += r * r;
      }
    double beta[3];
    for (int c = 0; c < 3; ++c) beta[c] = rz[c] > 0 ? rz_new[c] / rz[c] : 0.0;
    // P = D^-1 R + beta P
    for (Index i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) P(i, c) = R(i, c) * dinv[i] + beta[c] * P(i, c);
    for (int c = 0; c < 3; ++c) rz[c] = rz_new[c];
  }
  return it;
}

// Removes the per-component mean of the rows of X.
void remove_component_mean(const VectorXi& comp, Index n_comp, MatrixX3dR& X) {
  const Index n = static_cast<Index>(X.rows());
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(n_comp, 3);
  Eigen::VectorXd size = Eigen::VectorXd::Zero(n_comp);
  for (Index i = 0; i < n; ++i) {
    mean.row(comp[i]) += X.row(i);
    size[comp[i]] += 1;
  }
  for (Index c = 0; c < n_comp; ++c) mean.row(c) /= size[c];
  for (Index i = 0; i < n; ++i) X.row(i) -= mean.row(comp[i]);
}

}  // namespace

LaplacianEmbedResult laplacian_embed(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A,
                                     const LaplacianHistogram& hist,
                                     const std::vector<int>& pairs, const std::vector<int>& bits,
                                     const LaplacianEmbedOptions& opt) {
  const Index n = static_cast<Index>(V.rows());
  if (pairs.size() != bits.size()) throw MeshError("pairs and bits differ in length");
  if (opt.n_robust < 1) throw MeshError("n_robust must be >= 1, got " + std::to_string(opt.n_robust));
  const bool thesis_carrier = opt.carrier == LaplacianCarrier::Thesis && opt.compress == 0;
  if (!thesis_carrier && opt.thesis_exact) throw MeshError("thesis_exact uses the thesis carrier only");
  if (!thesis_carrier && !opt.triangles) throw MeshError("the Laplacian carrier needs the mesh's triangles");
  const double eps_measure = opt.thesis_exact ? opt.eps : 0.0;
  MatrixX3dR L;
  Eigen::VectorXd d;
  LaplacianCarrierField field;
  // The default carrier takes the fast path of laplacian_carrier.h (the scalar alone, the change for the
  // moved vertices only); the same values and changes, bit for bit, as the general one.
  const bool local_ring = opt.carrier == LaplacianCarrier::Local && opt.compress == 0;
  LocalRingCarrier ring;
  if (thesis_carrier) {
    L = laplacian_coordinates(V, A, eps_measure);  // eq. 7.1.2
    d = L.rowwise().norm() / opt.scale;             // eq. 7.1.5
  } else if (local_ring) {
    laplacian_local_ring(V, A, ring);
    d = ring.value;
  } else {
    field = laplacian_carrier(V, A, *opt.triangles, opt.carrier, opt.scale, true, opt.compress);
    d = field.value;
  }

  LaplacianEmbedResult R;
  R.d_target = d;
  R.n_moved = select_targets(d, hist, pairs, bits, opt, opt.thesis_exact, R.d_target).n_moved;
  MatrixX3dR dL;
  if (local_ring)
    laplacian_local_change(V, A, ring, R.d_target, dL);
  else
    dL = thesis_carrier ? length_change(L, d, R.d_target) : carrier_change(field, d, R.d_target);

  if (opt.thesis_exact) {
    // §7.2.2: X^ = M^-1 L^ with M = K - eps I (eq. 7.1.4), L^ = L + dL.
    R.V = solve(kirchhoff_matrix_shifted(A, -opt.eps), L + dL, false);
    R.rounds = 1;
    return R;
  }
  // meshmark: a Laplacian field must sum to zero on each component, so remove the per-component
  // mean of dL (what any geometry can realise), solve (K + eps' I) dX = dL with a tiny eps' that
  // only makes the system definite, and remove dX's per-component mean: no translation drift.
  Index n_comp = 0;
  std::vector<Index> order;  // breadth-first numbering, for the iterative solve
  const VectorXi comp = component_labels(A, n, n_comp, opt.iterations > 0 ? &order : nullptr);
  const double eps_solve = 1e-8;
  if (opt.iterations <= 0) {  // direct: one exact solve, as §7.2.2
    const Eigen::SparseMatrix<double> M = kirchhoff_matrix_shifted(A, eps_solve);
    R.V = V;
    VectorXb used(n);
    for (Index i = 0; i < n; ++i) used[i] = A.ptr[i + 1] > A.ptr[i] ? 1 : 0;
    for (int round = 0;; ++round) {
      remove_component_mean(comp, n_comp, dL);
      MatrixX3dR dX = solve(M, dL, true);
      remove_component_mean(comp, n_comp, dX);
      R.V += dX;
      R.rounds = round + 1;
      // The thesis carrier is reached by the one solve (L = K X is linear). The other carriers depend
      // on the 1-ring's edge lengths and normals too: re-read and top up, as the iterative rounds do.
      if (thesis_carrier || round + 1 >= opt.max_rounds) break;
      if (local_ring) {
        laplacian_local_ring(R.V, A, ring);
        d = ring.value;
      } else {
        field = laplacian_carrier(R.V, A, *opt.triangles, opt.carrier, opt.scale, true, opt.compress);
        d = field.value;
      }
      const LaplacianHistogram h = laplacian_histogram(d, hist.K, hist.lo, hist.hi, used);
      Eigen::VectorXd dt = d;
      const Selection S = select_targets(d, h, pairs, bits, opt, false, dt);
      if (S.short_pairs == 0) break;
      R.n_moved += S.n_moved;
      for (Index i = 0; i < n; ++i)
        if (dt[i] != d[i]) R.d_target[i] = dt[i];
      if (local_ring)
        laplacian_local_change(R.V, A, ring, dt, dL);
      else
        dL = carrier_change(field, d, dt);
    }
    return R;
  }
  // Iterative (default): the solve only has to put the histogram where the mark needs it. Each round
  // runs `iterations` PCG steps on the current length change, then re-reads the histogram and tops up
  // the pairs that lack part of their margin (eq. 7.2.16 recomputed on the current counts). See
  // docs/laplacian.md, "Iterative reconstruction". The rounds work on the vertices renumbered in
  // breadth-first order, so that the neighbours gathered by each PCG step sit close in memory.
  std::vector<Index> inv(static_cast<size_t>(n));
  for (Index k = 0; k < n; ++k) inv[order[k]] = k;
  const Adjacency Ap = permute_adjacency(A, order, inv);
  MatrixX3dR X(n, 3), dLp(n, 3);
  VectorXi comp_p(n);
  VectorXb mask(n);
  for (Index k = 0; k < n; ++k) {
    X.row(k) = V.row(order[k]);
    dLp.row(k) = dL.row(order[k]);
    comp_p[k] = comp[order[k]];
    mask[k] = Ap.ptr[k + 1] > Ap.ptr[k] ? 1 : 0;
  }
  MatrixX3iR Tp;  // the triangles in the breadth-first numbering (carriers other than the thesis')
  if (!thesis_carrier) {
    Tp.resize(opt.triangles->rows(), 3);
    for (Eigen::Index t = 0; t < Tp.rows(); ++t)
      for (int c = 0; c < 3; ++c) Tp(t, c) = inv[(*opt.triangles)(t, c)];
  }
  MatrixX3dR dX(n, 3);
  // the rounds' scalar in the breadth-first numbering: branch-free while the mesh fits in the cache
  // (laplacian_carrier.h; the same values either way)
  const bool ring_branch_free = n <= (Index(1) << 18);
  for (int round = 0;; ++round) {
    remove_component_mean(comp_p, n_comp, dLp);
    R.iterations += pcg(Ap, eps_solve, dLp, opt.iterations, dX);
    remove_component_mean(comp_p, n_comp, dX);
    X += dX;
    R.rounds = round + 1;
    if (round + 1 >= opt.max_rounds) break;
    if (thesis_carrier) {
      L = laplacian_coordinates(X, Ap, 0.0);
      d = L.rowwise().norm() / opt.scale;
    } else if (local_ring) {
      laplacian_local_ring(X, Ap, ring, ring_branch_free);
      d = ring.value;
    } else {
      field = laplacian_carrier(X, Ap, Tp, opt.carrier, opt.scale, true, opt.compress);
      d = field.value;
    }
    const LaplacianHistogram h = laplacian_histogram(d, hist.K, hist.lo, hist.hi, mask);
    Eigen::VectorXd dt = d;
    const Selection S = select_targets(d, h, pairs, bits, opt, false, dt);
    if (S.short_pairs == 0) break;
    R.n_moved += S.n_moved;
    for (Index k = 0; k < n; ++k)
      if (dt[k] != d[k]) R.d_target[order[k]] = dt[k];
    if (local_ring)
      laplacian_local_change(X, Ap, ring, dt, dLp);
    else
      dLp = thesis_carrier ? length_change(L, d, dt) : carrier_change(field, d, dt);
  }
  R.V.resize(n, 3);
  for (Index k = 0; k < n; ++k) R.V.row(order[k]) = X.row(k);
  return R;
}

}  // namespace meshmark
