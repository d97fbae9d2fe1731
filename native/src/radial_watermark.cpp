#include "meshmark/radial_watermark.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"
#include "meshmark/pca.h"
#include "meshmark/radial_distances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

namespace meshmark {

RadialOrigin radial_origin(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                           RadialOriginMode mode) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  Eigen::Index count = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) count += mask[i] != 0;
  if (count < 2) throw MeshError("the radial origin needs at least 2 (referenced) vertices");
  const PCAFrame f = pca_frame(V, mask);  // pass 1: centroid, covariance, first principal axis q
  const Eigen::Vector3d c = f.pca.centroid, q = f.pca.axes.col(0);
  const double lambda = f.pca.eigenvalues[0];
  const size_t n = static_cast<size_t>(f.n), h = n / 2;
  // Pass 2: the projections p on q (kept), their mean cube and range for meshmark's sign rule
  // (positive skewness, docs/mesh_model.md), and a counting pass for the right-most half: a
  // 4096-bucket histogram of p over [-R, R] (R bounds |p|) in which the bucket of the h-th value is
  // found, so that only that bucket is selected, instead of a selection over all N. The bucket index
  // is monotone in p.
  constexpr int B = 4096;
  const double R = f.radius > 0 ? f.radius : 1.0, scale = B / (2 * R);
  auto bucket = [&](double v) { return std::min(std::max(static_cast<int>((v + R) * scale), 0), B - 1); };
  Scratch<double> p;
  p.resize(n);
  std::vector<size_t> cnt(B, 0);
  std::vector<double> sum(B, 0.0);
  double s3 = 0, pmin = 0, pmax = 0;
  for (Eigen::Index i = 0, j = 0; i < V.rows(); ++i) {
    if (!mask[i]) continue;
    const double* v = row_ptr(V, i);
    const double pi = (v[0] - c[0]) * q[0] + (v[1] - c[1]) * q[1] + (v[2] - c[2]) * q[2];
    p[j++] = pi;
    s3 += pi * pi * pi;
    pmin = std::min(pmin, pi);
    pmax = std::max(pmax, pi);
    const int b = bucket(pi);
    ++cnt[b];
    sum[b] += pi;
  }
  const double m3 = s3 / static_cast<double>(n);
  const int sign = pca_axis_sign(m3, pmin, pmax, lambda, q);
  RadialOrigin o;
  o.axis = sign * q;
  o.skewness = lambda > 0 ? sign * m3 / std::pow(lambda, 1.5) : 0.0;
  // the right-most half: the floor(N/2) largest projections sign * p (the median vertex is left out
  // when N is odd)
  if (mode == RadialOriginMode::Axis) {
    // the sum of the h largest sign * p: whole buckets from the far end, then the cut bucket's largest
    size_t taken = 0;
    double s = 0;  // sum of p over the whole buckets taken
    const int step = sign > 0 ? -1 : 1, last = sign > 0 ? 0 : B - 1;
    int cut = sign > 0 ? B - 1 : 0;
    for (; cut != last && taken + cnt[cut] < h; cut += step) {
      taken += cnt[cut];
      s += sum[cut];
    }
    std::vector<double> part;  // sign * p of the cut bucket (ties are interchangeable)
    part.reserve(cnt[cut]);
    for (size_t j = 0; j < n; ++j)
      if (bucket(p[j]) == cut) part.push_back(sign * p[j]);
    const size_t r = h - taken;
    std::nth_element(part.begin(), part.begin() + (part.size() - r), part.end());
    double sp = 0;
    for (size_t j = part.size() - r; j < part.size(); ++j) sp += part[j];
    o.origin = c + ((sign * s + sp) / static_cast<double>(h)) * o.axis;
  } else {
    std::vector<Eigen::Index> row(n), idx(n);  // masked row of each projection; order by (sign p, position)
    for (Eigen::Index i = 0, j = 0; i < V.rows(); ++i)
      if (mask[i]) row[j++] = i;
    std::iota(idx.begin(), idx.end(), Eigen::Index(0));
    std::nth_element(idx.begin(), idx.begin() + (n - h), idx.end(), [&](Eigen::Index a, Eigen::Index b) {
      const double pa = sign * p[a], pb = sign * p[b];
      return pa < pb || (pa == pb && a < b);
    });
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (size_t i = n - h; i < n; ++i) s += V.row(row[idx[i]]).transpose();
    o.origin = s / static_cast<double>(h);
  }
  return o;
}

namespace {

// Eqs. 6.1.2-6.1.3 for one norm: 0-based bin, rho_max in B_K.
inline int radial_bin_of(double rho, double lo, double delta, int K) {
  const int k = static_cast<int>((rho - lo) / delta);  // eq. 6.1.3; floor, as rho >= rho_min
  return std::min(std::max(k, 0), K - 1);
}

void check_histogram(double lo, double hi, Eigen::Index m, int K) {
  if (K < 4) throw MeshError("the number of bins K must be at least 4, got " + std::to_string(K));
  if (m < K)
    throw MeshError("the mesh has " + std::to_string(m) + " vertices but " + std::to_string(K) +
                    " bins were asked for: fewer vertices than bins");
  if (!(hi - lo > 1e-10 * hi))  // equal up to rounding
    throw MeshError("all " + std::to_string(m) + " vertices are at the same distance from the origin: "
                    "the radial histogram has no range");
}

}  // namespace

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
  check_histogram(lo, hi, m, K);
  RadialHistogram h;
  h.K = K;
  h.rho_min = lo;
  h.rho_max = hi;
  h.delta = (hi - lo) / K;  // eq. 6.1.2
  h.bin = VectorXi::Constant(rho.size(), -1);
  h.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < rho.size(); ++i) {
    if (!mask[i]) continue;
    const int k = radial_bin_of(rho[i], lo, h.delta, K);
    h.bin[i] = k;
    ++h.counts[k];
  }
  return h;
}

RadialCounts radial_counts(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                           const Eigen::Vector3d& o) {
  Scratch<double> rho;
  rho.resize(V.rows());
  const RadialRange r = radial_range(V, mask, o, rho.data());  // eq. 6.1.1
  check_histogram(r.lo, r.hi, r.m, K);
  RadialCounts out;
  out.rho_min = r.lo;
  out.rho_max = r.hi;
  out.delta = (r.hi - r.lo) / K;  // eq. 6.1.2
  out.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (mask[i]) ++out.counts[radial_bin_of(rho[i], r.lo, out.delta, K)];
  return out;
}

namespace {

struct Once {
  MatrixX3dR V;
  std::vector<int> pairs, n_mov;
  int n_moved = 0;
};

// One embedding about the origin o (eqs. 6.1.1-6.1.7). One pass over the vertices for rho, its range
// and the copy of V into the output; one over rho for the histogram; one that collects the radii of
// the bins that give vertices and the extremes of the bins that receive them; then the moved rows.
Once embed_once(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                const std::vector<int>& pairs_in, const std::vector<int>& bits, int T, const Eigen::Vector3d& o,
                bool first_embeddable) {
  const Eigen::Index n = V.rows();
  Once out;
  prepare_output(out.V, n);
  Scratch<double> rhos;
  rhos.resize(n);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  Eigen::Index m = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* v = row_ptr(V, i);
    double* w = &out.V(i, 0);
    w[0] = v[0], w[1] = v[1], w[2] = v[2];  // rows not moved below are copied bit-exactly
    if (!mask[i]) continue;
    const double rho = vertex_distance(v, o);  // eq. 6.1.1
    rhos[i] = rho;
    lo = std::min(lo, rho);
    hi = std::max(hi, rho);
    ++m;
  }
  check_histogram(lo, hi, m, K);
  const double delta = (hi - lo) / K;  // eq. 6.1.2
  std::vector<Index> counts(K, 0);
  Scratch<Index> bins;
  bins.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {  // eq. 6.1.3
    const int k = mask[i] ? radial_bin_of(rhos[i], lo, delta, K) : -1;
    bins[i] = k;
    if (k >= 0) ++counts[k];
  }
  const int n_pairs = (K - 2) / 2;  // capacity floor((K-2)/2) (§6.3.1)
  out.pairs = pairs_in;
  if (first_embeddable) {  // the thesis' placement: bit i in the i-th embeddable pair (eq. 6.1.4)
    out.pairs.clear();
    for (int j = 0; j < n_pairs && out.pairs.size() < bits.size(); ++j)
      if (counts[2 * j + 1] + counts[2 * j + 2] >= 1) out.pairs.push_back(j);
    if (out.pairs.size() < bits.size())
      throw MeshError("the mesh offers " + std::to_string(out.pairs.size()) + " embeddable pairs with K=" +
                      std::to_string(K) + "; " + std::to_string(bits.size()) + " bits do not fit");
  }
  const std::vector<int>& pairs = out.pairs;
  auto edge = [&](int k) { return lo + delta * k; };
  // n_mov of every pair (cases 1-3, eq. 6.1.7), the bins that give vertices and those that receive them
  std::vector<char> gives(K, 0), receives(K, 0);
  for (size_t c = 0; c < pairs.size(); ++c) {
    const int a = 2 * pairs[c] + 1, b = a + 1, w = bits[c];  // B_k, B_k+1 (0-based)
    const int na = counts[a], nb = counts[b];
    const int src = w < 0 ? na : nb, dst = w < 0 ? nb : na;  // w = +1 mirrors w = -1
    int n_mov;
    if (dst - src >= T) n_mov = 0;                      // case 1
    else if (src + dst < T) n_mov = src;                // case 2
    else n_mov = (src - dst + T + 1) / 2;               // case 3, eq. 6.1.7: ceil((|B_k|-|B_k+1|+n_thr)/2)
    n_mov = std::min(n_mov, src);
    out.n_mov.push_back(n_mov);
    if (n_mov > 0) {
      gives[w < 0 ? a : b] = 1;
      receives[w < 0 ? b : a] = 1;
    }
  }
  // the radii (with rows) of the giving bins and the extreme radii of the receiving bins
  std::vector<std::vector<std::pair<double, Index>>> members(K);
  std::vector<double> bmin(K, std::numeric_limits<double>::infinity()), bmax(K, -std::numeric_limits<double>::infinity());
  for (int k = 0; k < K; ++k)
    if (gives[k]) members[k].reserve(counts[k]);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int k = bins[i];
    if (k < 0) continue;
    if (gives[k]) members[k].emplace_back(rhos[i], static_cast<Index>(i));
    if (receives[k]) {
      bmin[k] = std::min(bmin[k], rhos[i]);
      bmax[k] = std::max(bmax[k], rhos[i]);
    }
  }
  for (size_t c = 0; c < pairs.size(); ++c) {
    const int n_mov = out.n_mov[c];
    if (n_mov == 0) continue;
    const int a = 2 * pairs[c] + 1, b = a + 1, w = bits[c];
    // eq. 6.1.5: the moved radii go just inside the receiving bin's own extremes
    const int recv = w < 0 ? b : a;
    double lo_el = edge(recv), hi_el = edge(recv + 1);
    if (counts[recv] > 0) lo_el = bmin[recv], hi_el = bmax[recv];  // fallback: the bin's range edges
    if (hi_el <= lo_el) {  // single-valued bin: the far edge replaces the missing extreme
      if (w > 0) lo_el = edge(recv);
      else hi_el = edge(recv + 1);
    }
    // n* = the least integer n >= 3 with rho_min^{k+1} + delta/n < rho_max^{k+1} (mirrored for w = +1)
    const double n_star = std::max(3.0, std::floor(delta / (hi_el - lo_el)) + 1.0);
    const double target = w < 0 ? lo_el + delta / n_star : hi_el - delta / n_star;
    // the n_mov largest radii of B_k (w = -1) or the n_mov smallest of B_k+1 (w = +1); ties by row
    std::vector<std::pair<double, Index>>& s = members[w < 0 ? a : b];
    const size_t first = w < 0 ? s.size() - n_mov : 0;
    if (w < 0 && first > 0) std::nth_element(s.begin(), s.begin() + first, s.end());
    if (w > 0 && static_cast<size_t>(n_mov) < s.size()) std::nth_element(s.begin(), s.begin() + n_mov, s.end());
    for (size_t k = first; k < first + n_mov; ++k) {  // radial move (theta, phi of eq. 6.1.1 kept)
      const Index i = s[k].second;
      const double rho = s[k].first;
      if (target != rho && rho > 0) radial_move_row(row_ptr(V, i), &out.V(i, 0), o, rho, target);
    }
    out.n_moved += n_mov;
  }
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
  Eigen::Vector3d o_marked = o;
  if (opt.origin_iters > 0) o_marked = radial_origin(r.V, mask, opt.origin_mode).origin;
  best.drift = opt.origin_iters > 0 ? (o_marked - o).norm() : -1.0;
  best.origin = o;
  best.V = std::move(r.V);
  best.n_mov = r.n_mov;
  best.pairs = r.pairs;
  best.n_moved = r.n_moved;
  double drift = best.drift;
  int it = 0;
  // Re-synchronisation (docs/radial.md, not in the thesis); keeps the iterate with the smallest drift.
  for (; it < opt.origin_iters && drift > 0; ++it) {
    o = o_marked;
    r = embed_once(V, mask, K, pairs, bits, opt.n_thr, o, opt.first_embeddable);
    o_marked = radial_origin(r.V, mask, opt.origin_mode).origin;
    drift = (o_marked - o).norm();
    if (drift < best.drift) {
      best.drift = drift;
      best.origin = o;
      best.V = std::move(r.V);
      best.n_mov = r.n_mov;
      best.pairs = r.pairs;
      best.n_moved = r.n_moved;
    }
  }
  best.iterations = it;
  return best;
}

}  // namespace meshmark
