#include "meshmark/radial_watermark.h"
#include "meshmark/error.h"
#include "meshmark/pca.h"
#include "meshmark/radial_distances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace meshmark {

RadialOrigin radial_origin(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                           RadialOriginMode mode) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  Eigen::Index count = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) count += mask[i] != 0;
  if (count < 2) throw MeshError("the radial origin needs at least 2 (referenced) vertices");
  MatrixX3dR copy;
  if (count < V.rows()) {  // the masked vertices only
    copy.resize(count, 3);
    for (Eigen::Index i = 0, r = 0; i < V.rows(); ++i)
      if (mask[i]) copy.row(r++) = V.row(i);
  }
  const Eigen::Ref<const MatrixX3dR> P = count < V.rows() ? Eigen::Ref<const MatrixX3dR>(copy) : V;
  const PCA pc = pca(P);  // sign rule: positive third central moment (docs/mesh_model.md)
  const Eigen::Vector3d u = pc.axes.col(0);
  const Eigen::Index n = P.rows(), h = n / 2;
  std::vector<double> p(n);
  for (Eigen::Index i = 0; i < n; ++i)
    p[i] = (P(i, 0) - pc.centroid[0]) * u[0] + (P(i, 1) - pc.centroid[1]) * u[1] + (P(i, 2) - pc.centroid[2]) * u[2];
  RadialOrigin o;
  o.axis = u;
  o.skewness = pc.eigenvalues[0] > 0 ? pc.skewness[0] / std::pow(pc.eigenvalues[0], 1.5) : 0.0;
  // the right-most half: the floor(N/2) largest projections (the median vertex is left out when N is odd)
  if (mode == RadialOriginMode::Axis) {
    std::nth_element(p.begin(), p.begin() + (n - h), p.end());  // ties at the cut are interchangeable
    double s = 0;
    for (Eigen::Index i = n - h; i < n; ++i) s += p[i];
    o.origin = pc.centroid + (s / h) * u;
  } else {
    std::vector<Eigen::Index> idx(n);
    std::iota(idx.begin(), idx.end(), Eigen::Index(0));
    std::nth_element(idx.begin(), idx.begin() + (n - h), idx.end(),
                     [&](Eigen::Index a, Eigen::Index b) { return p[a] < p[b] || (p[a] == p[b] && a < b); });
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (Eigen::Index i = n - h; i < n; ++i) s += P.row(idx[i]).transpose();
    o.origin = s / static_cast<double>(h);
  }
  return o;
}

RadialHistogram radial_histogram(const Eigen::Ref<const Eigen::VectorXd>& rho, int K,
                                 const Eigen::Ref<const VectorXb>& mask) {
  if (K < 4) throw MeshError("the number of bins K must be at least 4, got " + std::to_string(K));
  if (mask.size() != rho.size()) throw MeshError("mask and rho differ in length");
  Eigen::Index m = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (Eigen::Index i = 0; i < rho.size(); ++i)
    if (mask[i]) {
      ++m;
      lo = std::min(lo, rho[i]);
      hi = std::max(hi, rho[i]);
    }
  if (m < K)
    throw MeshError("the mesh has " + std::to_string(m) + " vertices but " + std::to_string(K) +
                    " bins were asked for: fewer vertices than bins");
  if (!(hi - lo > 1e-10 * hi))  // equal up to rounding
    throw MeshError("all " + std::to_string(m) + " vertices are at the same distance from the origin: "
                    "the radial histogram has no range");
  RadialHistogram h;
  h.K = K;
  h.rho_min = lo;
  h.rho_max = hi;
  h.delta = (hi - lo) / K;  // eq. 6.1.2
  h.bin = VectorXi::Constant(rho.size(), -1);
  h.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < rho.size(); ++i) {
    if (!mask[i]) continue;
    int k = static_cast<int>(std::floor((rho[i] - lo) / h.delta));  // eq. 6.1.3
    k = std::min(std::max(k, 0), K - 1);                            // rho_max belongs to B_K
    h.bin[i] = k;
    ++h.counts[k];
  }
  return h;
}

namespace {

struct Once {
  MatrixX3dR V;
  std::vector<int> pairs, n_mov;
  int n_moved = 0;
};

Once embed_once(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                const std::vector<int>& pairs_in, const std::vector<int>& bits, int T, const Eigen::Vector3d& o,
                bool first_embeddable) {
  const Eigen::VectorXd rho = radial_distances(V, mask, o);  // eq. 6.1.1
  const RadialHistogram h = radial_histogram(rho, K, mask);  // eqs. 6.1.2-6.1.3
  Once out;
  out.pairs = pairs_in;
  if (first_embeddable) {  // the thesis' placement: bit i in the i-th embeddable pair (eq. 6.1.4)
    out.pairs.clear();
    for (int j = 0; j < h.n_pairs() && out.pairs.size() < bits.size(); ++j)
      if (h.counts[2 * j + 1] + h.counts[2 * j + 2] >= 1) out.pairs.push_back(j);
    if (out.pairs.size() < bits.size())
      throw MeshError("the mesh offers " + std::to_string(out.pairs.size()) + " embeddable pairs with K=" +
                      std::to_string(K) + "; " + std::to_string(bits.size()) + " bits do not fit");
  }
  const std::vector<int>& pairs = out.pairs;
  const Eigen::Index n = rho.size();
  std::vector<Index> start(K + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i)
    if (h.bin[i] >= 0) ++start[h.bin[i] + 1];
  for (int k = 0; k < K; ++k) start[k + 1] += start[k];
  std::vector<Index> fill(start.begin(), start.end() - 1), member(start[K]);
  for (Eigen::Index i = 0; i < n; ++i)
    if (h.bin[i] >= 0) member[fill[h.bin[i]]++] = static_cast<Index>(i);
  auto edge = [&](int k) { return h.rho_min + h.delta * k; };

  Eigen::VectorXd rho_new = rho;
  for (size_t c = 0; c < pairs.size(); ++c) {
    const int a = 2 * pairs[c] + 1, b = a + 1, w = bits[c];  // B_k, B_k+1 (0-based)
    const int na = h.counts[a], nb = h.counts[b];
    const int src = w < 0 ? na : nb, dst = w < 0 ? nb : na;  // w = +1 mirrors w = -1
    int n_mov;
    if (dst - src >= T) n_mov = 0;                      // case 1
    else if (src + dst < T) n_mov = src;                // case 2
    else n_mov = (src - dst + T + 1) / 2;               // case 3, eq. 6.1.7: ceil((|B_k|-|B_k+1|+n_thr)/2)
    n_mov = std::min(n_mov, src);
    out.n_mov.push_back(n_mov);
    if (n_mov == 0) continue;
    // eq. 6.1.5: the moved radii go just inside the receiving bin's own extremes
    const int recv = w < 0 ? b : a;
    double lo_el = edge(recv), hi_el = edge(recv + 1);
    if (h.counts[recv] > 0) {  // extremes of the receiving bin's contents (fallback: its range edges)
      lo_el = std::numeric_limits<double>::infinity();
      hi_el = -lo_el;
      for (Index k = start[recv]; k < start[recv + 1]; ++k) {
        lo_el = std::min(lo_el, rho[member[k]]);
        hi_el = std::max(hi_el, rho[member[k]]);
      }
    }
    if (hi_el <= lo_el) {  // single-valued bin: the far edge replaces the missing extreme
      if (w > 0) lo_el = edge(recv);
      else hi_el = edge(recv + 1);
    }
    // n* = the least integer n >= 3 with rho_min^{k+1} + delta/n < rho_max^{k+1} (mirrored for w = +1)
    const double n_star = std::max(3.0, std::floor(h.delta / (hi_el - lo_el)) + 1.0);
    const double target = w < 0 ? lo_el + h.delta / n_star : hi_el - h.delta / n_star;
    // the n_mov largest radii of B_k (w = -1) or the n_mov smallest of B_k+1 (w = +1); ties by index
    const int from = w < 0 ? a : b;
    std::vector<Index> s(member.begin() + start[from], member.begin() + start[from + 1]);
    auto less = [&](Index i, Index j) { return rho[i] < rho[j] || (rho[i] == rho[j] && i < j); };
    const size_t first = w < 0 ? s.size() - n_mov : 0;
    if (w < 0 && first > 0) std::nth_element(s.begin(), s.begin() + first, s.end(), less);
    if (w > 0 && static_cast<size_t>(n_mov) < s.size()) std::nth_element(s.begin(), s.begin() + n_mov, s.end(), less);
    for (size_t k = first; k < first + n_mov; ++k) rho_new[s[k]] = target;
    out.n_moved += n_mov;
  }
  out.V = radial_rescale(V, o, rho, rho_new);  // radial move: theta, phi of eq. 6.1.1 kept
  return out;
}

}  // namespace

RadialEmbedResult radial_embed(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                               const std::vector<int>& pairs, const std::vector<int>& bits,
                               const RadialEmbedOptions& opt) {
  if (!opt.first_embeddable && pairs.size() != bits.size()) throw MeshError("pairs and bits differ in length");
  if (K < 4) throw MeshError("the number of bins K must be at least 4, got " + std::to_string(K));
  for (size_t c = 0; c < pairs.size(); ++c) {
    if (pairs[c] < 0 || pairs[c] >= (K - 2) / 2)
      throw MeshError("pair " + std::to_string(pairs[c]) + " is outside 0.." + std::to_string((K - 2) / 2 - 1));
    if (bits[c] != 1 && bits[c] != -1) throw MeshError("bits must be +1 or -1");
  }
  if (opt.n_thr < 1) throw MeshError("n_thr must be >= 1, got " + std::to_string(opt.n_thr));
  Eigen::Vector3d o = radial_origin(V, mask, opt.origin_mode).origin;
  Once r = embed_once(V, mask, K, pairs, bits, opt.n_thr, o, opt.first_embeddable);
  RadialEmbedResult best;
  // the drift costs a PCA of the marked mesh: measured only when re-synchronising (else -1, unknown)
  best.drift = opt.origin_iters > 0 ? (radial_origin(r.V, mask, opt.origin_mode).origin - o).norm() : -1.0;
  best.origin = o;
  best.V = r.V;
  best.n_mov = r.n_mov;
  best.pairs = r.pairs;
  best.n_moved = r.n_moved;
  double drift = best.drift;
  int it = 0;
  // Re-synchronisation (docs/radial.md, not in the thesis); keeps the iterate with the smallest drift.
  for (; it < opt.origin_iters && drift > 0; ++it) {
    o = radial_origin(r.V, mask, opt.origin_mode).origin;
    r = embed_once(V, mask, K, pairs, bits, opt.n_thr, o, opt.first_embeddable);
    drift = (radial_origin(r.V, mask, opt.origin_mode).origin - o).norm();
    if (drift < best.drift) {
      best.drift = drift;
      best.origin = o;
      best.V = r.V;
      best.n_mov = r.n_mov;
      best.pairs = r.pairs;
      best.n_moved = r.n_moved;
    }
  }
  best.iterations = it;
  return best;
}

}  // namespace meshmark
