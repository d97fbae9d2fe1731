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

// Per-component labels of the edge graph (BFS over the CSR adjacency).
VectorXi component_labels(const Adjacency& A, Index n, Index& count) {
  VectorXi label = VectorXi::Constant(n, -1);
  std::vector<Index> stack;
  count = 0;
  for (Index s = 0; s < n; ++s) {
    if (label[s] >= 0) continue;
    label[s] = count;
    stack.assign(1, s);
    while (!stack.empty()) {
      const Index v = stack.back();
      stack.pop_back();
      for (Offset k = A.ptr[v]; k < A.ptr[v + 1]; ++k)
        if (label[A.nbr[k]] < 0) {
          label[A.nbr[k]] = count;
          stack.push_back(A.nbr[k]);
        }
    }
    ++count;
  }
  return label;
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

}  // namespace

LaplacianEmbedResult laplacian_embed(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A,
                                     const LaplacianHistogram& hist,
                                     const std::vector<int>& pairs, const std::vector<int>& bits,
                                     const LaplacianEmbedOptions& opt) {
  const Index n = static_cast<Index>(V.rows());
  if (pairs.size() != bits.size()) throw MeshError("pairs and bits differ in length");
  if (opt.n_robust < 1) throw MeshError("n_robust must be >= 1, got " + std::to_string(opt.n_robust));
  const double eps_measure = opt.thesis_exact ? opt.eps : 0.0;
  const MatrixX3dR L = laplacian_coordinates(V, A, eps_measure);  // eq. 7.1.2
  Eigen::VectorXd d = L.rowwise().norm() / opt.scale;               // eq. 7.1.5

  // Members of every bin, in ascending order of d (eq. 7.2.13).
  std::vector<Offset> start(static_cast<size_t>(hist.K) + 1, 0);
  for (Index i = 0; i < n; ++i)
    if (hist.bin[i] >= 0) ++start[hist.bin[i] + 1];
  for (int k = 0; k < hist.K; ++k) start[k + 1] += start[k];
  std::vector<Index> members(static_cast<size_t>(start[hist.K]));
  {
    std::vector<Offset> fill(start.begin(), start.end() - 1);
    for (Index i = 0; i < n; ++i)
      if (hist.bin[i] >= 0) members[fill[hist.bin[i]]++] = i;
  }

  LaplacianEmbedResult R;
  R.d_target = d;
  for (size_t c = 0; c < pairs.size(); ++c) {
    const int j = pairs[c];
    if (j < 0 || j >= hist.n_pairs()) throw MeshError("pair index " + std::to_string(j) + " out of range");
    const int k1 = 2 * j + 1, k2 = 2 * j + 2;  // thesis bins B_{2j+2}, B_{2j+3}
    const int b = bits[c];
    const Offset n1 = start[k1 + 1] - start[k1], n2 = start[k2 + 1] - start[k2];
    const Offset f = n1 + n2;
    if (f == 0) continue;
    // The bin that must win: k1 for +1 (|B^k1| >= |B^k2|), k2 for -1 (eq. 7.1.9).
    const int win = b > 0 ? k1 : k2, lose = b > 0 ? k2 : k1;
    const Offset n_win = b > 0 ? n1 : n2, n_lose = f - n_win;
    const Offset margin = (f - 1) / opt.n_robust;
    // eq. 7.2.16: n = |B_lose| - floor((f-1)/2) + floor((f-1)/n_robust), at most |B_lose|.
    Offset n_move = n_lose - (f - 1) / 2 + margin;
    const bool satisfied = b > 0 ? n1 >= n2 : n1 < n2;
    if (opt.thesis_exact && satisfied) n_move = 0;  // Case 1: no alteration
    n_move = std::min(std::max<Offset>(n_move, 0), n_lose);
    if (n_move == 0) continue;
    // Target value (eq. 7.2.15): mean of the winning bin, or its centre when empty.
    const double lo_w = hist.lo + hist.delta * win;
    double dbar = lo_w + 0.5 * hist.delta;
    if (n_win > 0) {
      double s = 0;
      for (Offset m = start[win]; m < start[win + 1]; ++m) s += d[members[m]];
      dbar = s / static_cast<double>(n_win);
    }
    if (!opt.thesis_exact)  // keep moved lengths off the bin edges (float32/OBJ rounding)
      dbar = std::min(std::max(dbar, lo_w + 0.25 * hist.delta), lo_w + 0.75 * hist.delta);
    // Move the elements of the losing bin nearest to the winning one: the smallest of B_k2 for +1,
    // the largest of B_k1 for -1 (eqs. 7.2.13-7.2.14).
    std::vector<Index> lose_members(members.begin() + start[lose], members.begin() + start[lose + 1]);
    std::sort(lose_members.begin(), lose_members.end(), [&](Index a, Index c2) {
      return d[a] < d[c2] || (d[a] == d[c2] && a < c2);
    });
    for (Offset m = 0; m < n_move; ++m) {
      const Index i = b > 0 ? lose_members[m] : lose_members[lose_members.size() - 1 - m];
      R.d_target[i] = dbar;
      ++R.n_moved;
    }
  }

  // eq. 7.2.19: L^_i = L_i d^_i / d_i, only where d changed.
  MatrixX3dR dL = MatrixX3dR::Zero(n, 3);
  for (Index i = 0; i < n; ++i)
    if (R.d_target[i] != d[i] && d[i] > 0) dL.row(i) = L.row(i) * (R.d_target[i] / d[i] - 1.0);

  // Kirchhoff matrix (eq. 7.1.3) assembled straight from the sorted CSR adjacency, with `shift`
  // added to the diagonal (eq. 7.1.4 uses -eps).
  auto kirchhoff = [&](double shift) {
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
  };

  if (opt.thesis_exact) {
    // §7.2.2: X^ = M^-1 L^ with M = K - eps I (eq. 7.1.4), L^ = L + dL.
    R.V = solve(kirchhoff(-opt.eps), L + dL, false);
    return R;
  }
  // meshmark: a Laplacian field must sum to zero on each component, so remove the per-component
  // mean of dL (what any geometry can realise), solve (K + eps' I) dX = dL with a tiny eps' that
  // only makes the system definite, and remove dX's per-component mean: no translation drift.
  Index n_comp = 0;
  const VectorXi comp = component_labels(A, n, n_comp);
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(n_comp, 3);
  Eigen::VectorXd size = Eigen::VectorXd::Zero(n_comp);
  for (Index i = 0; i < n; ++i) {
    mean.row(comp[i]) += dL.row(i);
    size[comp[i]] += 1;
  }
  for (Index c = 0; c < n_comp; ++c) mean.row(c) /= size[c];
  for (Index i = 0; i < n; ++i) dL.row(i) -= mean.row(comp[i]);
  const double eps_solve = 1e-8;
  MatrixX3dR dX = solve(kirchhoff(eps_solve), dL, true);
  mean.setZero();
  for (Index i = 0; i < n; ++i) mean.row(comp[i]) += dX.row(i);
  for (Index c = 0; c < n_comp; ++c) mean.row(c) /= size[c];
  for (Index i = 0; i < n; ++i) dX.row(i) -= mean.row(comp[i]);
  R.V = V + dX;
  return R;
}

}  // namespace meshmark
