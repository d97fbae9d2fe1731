#include "meshmark/cho_watermark.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"
#include "meshmark/radial_distances.h"
#include "meshmark/vector_math.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace meshmark {

namespace {

// Cho step 2: W = (rho_max - rho_min) / N over the masked norms, with the errors of cho_bins.
struct ChoRange {
  double lo = 0, hi = 0, W = 0;
  Eigen::Index i_lo = -1, i_hi = -1;  // the two reference vertices: the first at rho_min / rho_max
};

ChoRange cho_range(double lo, double hi, Eigen::Index i_lo, Eigen::Index i_hi, Eigen::Index m, int K) {
  if (K < 1) throw MeshError("the number of bins K must be at least 1, got " + std::to_string(K));
  if (m < K)
    throw MeshError("the mesh has " + std::to_string(m) + " vertices but " + std::to_string(K) +
                    " bins were asked for: fewer vertices than bins");
  if (!(hi - lo > 1e-10 * hi))  // equal up to rounding
    throw MeshError("all " + std::to_string(m) + " vertices are at the same distance from the centre: "
                    "the vertex-norm histogram has no range");
  return {lo, hi, (hi - lo) / K, i_lo, i_hi};
}

ChoRange cho_range(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                   const Eigen::Vector3d& c, int K, double* rho) {
  const RadialRange r = radial_range(V, mask, c, rho);  // Cho step 1, one pass (rho stored if given)
  return cho_range(r.lo, r.hi, r.i_lo, r.i_hi, r.m, K);
}

// Cho steps 2-3 for one norm: its bin (bins of equal range W) and x in [0, 1], normalised with the
// bin's range. A norm on an interior boundary goes to the upper bin; rho_max to the last bin.
inline int cho_bin_of(double rho, const ChoRange& r, int K, double& x) {
  int k = static_cast<int>((rho - r.lo) / r.W);  // floor: the quotient is >= 0 (rho_min is the least norm)
  k = std::min(std::max(k, 0), K - 1);
  x = std::min(std::max((rho - (r.lo + r.W * k)) / r.W, 0.0), 1.0);  // Cho step 3
  return k;
}

inline double cho_value(double x, ChoMethod method) { return method == ChoMethod::Mean ? x : (2 * x - 1) * (2 * x - 1); }

}  // namespace

ChoBins cho_bins(const Eigen::Ref<const Eigen::VectorXd>& rho, int K, const Eigen::Ref<const VectorXb>& mask) {
  if (K < 1) throw MeshError("the number of bins K must be at least 1, got " + std::to_string(K));
  if (mask.size() != rho.size()) throw MeshError("mask and rho differ in length");
  const Eigen::Index n = rho.size();
  Eigen::Index m = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  Eigen::Index i_lo = -1, i_hi = -1;
  for (Eigen::Index i = 0; i < n; ++i)
    if (mask[i]) {
      ++m;
      if (rho[i] < lo) lo = rho[i], i_lo = i;
      if (rho[i] > hi) hi = rho[i], i_hi = i;
    }
  const ChoRange r = cho_range(lo, hi, i_lo, i_hi, m, K);
  ChoBins b;
  b.K = K;
  b.rho_min = r.lo;
  b.rho_max = r.hi;
  b.width = r.W;
  b.bin = VectorXi::Constant(n, -1);
  b.x = Eigen::VectorXd::Zero(n);
  b.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < n; ++i) {
    // Cho's strict inequalities leave the reference vertices out of every bin. Only one vertex at each
    // extreme is left out: other vertices tied with it (mirror-symmetric models) stay in the end bins
    // at x = 0 or 1, so a rounding that breaks the tie (rotation, float32) changes no bin.
    if (!mask[i] || i == i_lo || i == i_hi) continue;
    const int k = cho_bin_of(rho[i], r, K, b.x[i]);
    b.bin[i] = k;
    ++b.counts[k];
  }
  return b;
}

Eigen::VectorXd cho_statistics(const ChoBins& bins, ChoMethod method) {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(bins.K);
  for (Eigen::Index i = 0; i < bins.bin.size(); ++i) {
    const int k = bins.bin[i];
    if (k < 0) continue;
    s[k] += cho_value(bins.x[i], method);
  }
  for (int k = 0; k < bins.K; ++k) s[k] /= std::max(bins.counts[k], 1);
  return s;
}

ChoStatistics cho_statistics(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                             ChoMethod method) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  ChoStatistics out;
  out.center = masked_centroid(V, mask);  // Cho step 1 (pass 1)
  Scratch<double> rho;
  rho.resize(V.rows());
  const ChoRange r = cho_range(V, mask, out.center, K, rho.data());  // Cho step 2 (pass 2)
  out.stat = Eigen::VectorXd::Zero(K);
  out.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {  // Cho step 3 and the bin sums (pass 3, over rho)
    if (!mask[i] || i == r.i_lo || i == r.i_hi) continue;
    double x;
    const int k = cho_bin_of(rho[i], r, K, x);
    out.stat[k] += cho_value(x, method);
    ++out.counts[k];
  }
  for (int k = 0; k < K; ++k) out.stat[k] /= std::max(out.counts[k], 1);  // eq. 6.4.13 (method I)
  return out;
}

namespace {

// Statistic of one bin for exponent k from l = ln x (mean) or l = ln|2x-1| (variance), and its
// derivative in k: the histogram mapping of Cho step 4 (Figs. 2.4-2.5), x' = x^k or
// 2x'-1 = sgn(y)|y|^k with y = 2x-1, and the bin mean of x' or of (2x'-1)^2. guard (not in the
// paper) clips x' to [guard, 1-guard], only when k != 1. a is scratch for the n powers.
double bin_stat(const double* l, Index n, double k, ChoMethod method, double guard, double* a, double& dsdk) {
  constexpr double kNegInf = -std::numeric_limits<double>::infinity();
  exp_scaled(l, k, a, n);  // x^k or |y|^k (0 where l = -inf)
  double s = 0, d = 0;
  const bool g = guard > 0 && k != 1.0;
  if (method == ChoMethod::Mean) {
    for (Index j = 0; j < n; ++j) {
      const double v = a[j];
      if (l[j] == kNegInf) s += g ? guard : 0.0;  // x = 0
      else if (g && v < guard) s += guard;
      else if (g && v > 1 - guard) s += 1 - guard;
      else {
        s += v;
        d += l[j] * v;
      }
    }
  } else {
    const double cap = 1 - 2 * guard;
    for (Index j = 0; j < n; ++j) {
      if (l[j] == kNegInf) continue;  // y = 0
      const double v = a[j];
      if (g && v > cap) s += cap * cap;
      else {
        s += v * v;  // y'^2 = |y|^(2k)
        d += 2 * l[j] * v * v;
      }
    }
  }
  dsdk = d / n;
  return s / n;
}

// Per-vertex and per-bin scratch of one embedding, kept across the re-synchronisation rounds.
struct Workspace {
  Scratch<double> rho;       // (n,) ||v_i - c|| (Cho step 1)
  Scratch<Index> bin;        // (n,) bin of each vertex, -1 outside every bin
  std::vector<Index> start;  // (K+1,) offsets of the searched bins in g (other bins empty)
  Scratch<double> g;         // the searched bins' vertices grouped by bin, in vertex order: ln x (mean) or
                             // ln|2x-1| (variance); after the search the mapped x^k or |2x-1|^k
  Scratch<signed char> sy;   // (variance) sign of y = 2x-1 of the grouped vertices
  Scratch<double> a;         // powers of one bin (bin_stat)
};

struct OnceResult {
  MatrixX3dR V;
  Eigen::Vector3d centroid;  // masked centroid of V (the blind detector's centre)
  int evaluations = 0;
  Eigen::VectorXd k;
  std::vector<int> failed;
  int n_moved = 0;
};

// One embedding about the centre c (Cho steps 1-6) into out (whose buffer is reused when it has the
// right size). Sequential passes over the vertices: rho and its range; the bins with the k = 1
// statistic; the grouping of the searched bins (then their ln, vectorised); the mapping, written
// with the copy of the unmoved rows and the marked mesh's centroid. Per-vertex scratch: rho and the
// bin (12 bytes), plus 8 bytes (9 for the variance method) for each vertex of a searched bin.
void embed_once(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                const std::vector<int>& bins_used, const std::vector<int>& bits, const ChoEmbedOptions& o,
                const Eigen::Vector3d& c, Workspace& ws, OnceResult& out) {
  const Eigen::Index n = V.rows();
  ws.rho.resize(n);
  const ChoRange r = cho_range(V, mask, c, K, ws.rho.data());  // Cho steps 1-2
  const bool mean = o.method == ChoMethod::Mean;
  ws.bin.resize(n);
  std::vector<double> s1(K, 0.0);  // sum of x (mean) or (2x-1)^2 (variance): the statistic at k = 1
  std::vector<Index> cnt(K, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!mask[i] || i == r.i_lo || i == r.i_hi) {  // masked out, or a reference vertex (see cho_bins)
      ws.bin[i] = -1;
      continue;
    }
    double x;
    const int k = cho_bin_of(ws.rho[i], r, K, x);  // Cho steps 2-3
    ws.bin[i] = k;
    ++cnt[k];
    s1[k] += mean ? x : (2 * x - 1) * (2 * x - 1);
  }
  const double ref = mean ? 0.5 : 1.0 / 3.0;
  // h(m) >= 0 <=> the condition of Cho step 4 holds at step m; h(0) from the k = 1 statistic
  auto h_of = [&](int w, double s) { return w > 0 ? s - (ref + o.alpha) : (ref - o.alpha) - s; };
  std::vector<char> need(K, 0);  // bins whose k is searched: they carry a bit not yet satisfied
  for (size_t c2 = 0; c2 < bins_used.size(); ++c2) {
    const int bin = bins_used[c2];
    if (cnt[bin] > 0 && h_of(bits[c2], s1[bin] / cnt[bin]) < 0) need[bin] = 1;
  }
  // group x or |y| of those bins contiguously (counting sort, stable), then take their logarithms with
  // the derivative of the statistic at k = 1 (dS/dk = mean of x ln x or 2 y^2 ln|y|; first estimate)
  ws.start.assign(K + 1, 0);
  Index largest = 0;
  for (int k = 0; k < K; ++k) {
    ws.start[k + 1] = ws.start[k] + (need[k] ? cnt[k] : 0);
    if (need[k]) largest = std::max(largest, cnt[k]);
  }
  ws.g.resize(ws.start[K]);
  if (!mean) ws.sy.resize(ws.start[K]);
  ws.a.resize(largest);
  std::vector<Index> fill(ws.start.begin(), ws.start.end() - 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int k = ws.bin[i];
    if (k < 0 || !need[k]) continue;
    double x;
    cho_bin_of(ws.rho[i], r, K, x);  // the x of the binning pass, recomputed
    if (mean) {
      ws.g[fill[k]++] = x;
    } else {
      const double y = 2 * x - 1;
      ws.sy[fill[k]] = y < 0 ? -1 : (y > 0 ? 1 : 0);
      ws.g[fill[k]++] = std::abs(y);
    }
  }
  std::vector<double> d1(K, 0.0);
  for (int k = 0; k < K; ++k)
    if (need[k]) d1[k] = (mean ? 1.0 : 2.0) * log_inplace_moment(ws.g.data() + ws.start[k], cnt[k], mean ? 1 : 2);

  out.evaluations = 0;
  out.failed.clear();
  out.n_moved = 0;
  out.k = Eigen::VectorXd::Ones(K);
  const long m_up = std::lround((o.k_max - 1.0) / o.delta_k);    // k = 1 + m dk <= k_max   (w = -1)
  const long m_dn = std::lround((1.0 - o.delta_k) / o.delta_k);  // k = 1 - m dk >= dk      (w = +1)
  for (size_t c2 = 0; c2 < bins_used.size(); ++c2) {
    const int bin = bins_used[c2], w = bits[c2];
    const Index count = cnt[bin];
    const double h0 = count ? h_of(w, s1[bin] / count) : h_of(w, 0.0);
    if (h0 >= 0 && count > 0) continue;  // already on the right side: k = 1, bin untouched
    const long m_hi = w > 0 ? m_dn : m_up;
    auto k_of = [&](long m) { return w > 0 ? 1.0 - m * o.delta_k : 1.0 + m * o.delta_k; };
    if (count == 0) {
      out.failed.push_back(bin);
      out.k[bin] = h0 >= 0 ? 1.0 : k_of(m_hi);
      continue;
    }
    const double* lb = ws.g.data() + ws.start[bin];
    // h increases with m. Root estimates come from Newton's method on 1/S, which is nearly linear in
    // k (exactly 1/(k+1) or 1/(2k+1) for uniform x): from S and dS/dk at step m, with dk/dm = -dk
    // (w = +1) or +dk (w = -1). They only choose where to evaluate next.
    const double target = w > 0 ? ref + o.alpha : ref - o.alpha, dkdm = w > 0 ? -o.delta_k : o.delta_k;
    auto estimate = [&](long m, double s, double dsdk) {
      const double dg = -dsdk / (s * s) * dkdm;  // d(1/S)/dm
      return s > 0 && dg != 0 ? m - (1.0 / s - 1.0 / target) / dg : std::numeric_limits<double>::quiet_NaN();
    };
    double guess = 0;
    auto h = [&](long m) {
      ++out.evaluations;
      double dsdk = 0;
      const double s = bin_stat(lb, count, k_of(m), o.method, o.guard, ws.a.data(), dsdk);
      guess = estimate(m, s, dsdk);
      return h_of(w, s);
    };
    guess = estimate(0, s1[bin] / count, d1[bin] / count);
    // The first step m with h(m) >= 0 (= the sequential search of Cho step 4), by a safeguarded
    // search on integer m inside the bracket h(lo) < 0 <= h(hi): the next step is ceil(estimate), the
    // first integer at or right of the estimated root (so the search ends by evaluating the two steps
    // around the root), or the bisection when the estimate is off. h(m_hi) is only evaluated when no
    // smaller step satisfies the condition.
    long lo = 0, hi = m_hi;
    for (int it = 0; hi - lo > 1; ++it) {
      long cand = lo + (hi - lo) / 2;
      if (it < 24 && std::isfinite(guess)) {
        const double c = std::ceil(guess);
        if (c > lo && c < hi) cand = static_cast<long>(c);
        else if (c <= lo && c > lo - 2) cand = lo + 1;   // root just right of lo
        else if (c >= hi && c < hi + 2) cand = hi - 1;   // root just left of (or at) hi
      }
      if (h(cand) >= 0) hi = cand;
      else lo = cand;
    }
    if (hi == m_hi && h(m_hi) < 0) out.failed.push_back(bin);  // the limit k = dk or k_max is not enough
    out.k[bin] = k_of(hi);
  }
  // Cho step 4's mapping of the moved bins, vectorised: g <- x^k or |y|^k
  for (int k = 0; k < K; ++k)
    if (need[k] && out.k[k] != 1.0)
      exp_scaled(ws.g.data() + ws.start[k], out.k[k], ws.g.data() + ws.start[k], ws.start[k + 1] - ws.start[k]);
  // Cho step 5: denormalise with the same bin range, move radially (theta, phi kept); every other
  // row is copied bit-exactly. The centroid of the result is summed in the same order as masked_centroid.
  prepare_output(out.V, n);
  std::copy(ws.start.begin(), ws.start.end() - 1, fill.begin());
  double c0 = 0, c1 = 0, c2 = 0;
  Eigen::Index m = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* v = row_ptr(V, i);
    double* w = &out.V(i, 0);
    const int k = ws.bin[i];
    bool moved = false;
    if (k >= 0 && need[k] && out.k[k] != 1.0) {
      const Index j = fill[k]++;
      const double a = ws.g[j];  // x^k or |y|^k
      const double rho = ws.rho[i];
      double xm = a;  // x' (Figs. 2.4-2.5)
      if (!mean) xm = std::min(std::max(0.5 * (ws.sy[j] * a + 1), 0.0), 1.0);  // 2x' - 1 = sgn(y)|y|^k
      if (o.guard > 0) xm = std::min(std::max(xm, o.guard), 1 - o.guard);
      const double rho_new = r.lo + r.W * (k + xm);  // Cho step 5: the same bin range
      if (rho_new != rho) {
        ++out.n_moved;
        if (rho > 0) {
          radial_move_row(v, w, c, rho, rho_new);
          moved = true;
        }
      }
    }
    if (!moved) w[0] = v[0], w[1] = v[1], w[2] = v[2];
    if (mask[i]) {
      c0 += w[0];
      c1 += w[1];
      c2 += w[2];
      ++m;
    }
  }
  out.centroid = Eigen::Vector3d(c0, c1, c2) / static_cast<double>(m);
}

}  // namespace

ChoEmbedResult cho_embed(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                         const std::vector<int>& bins_used, const std::vector<int>& bits,
                         const ChoEmbedOptions& o) {
  if (bins_used.size() != bits.size()) throw MeshError("bins and bits differ in length");
  for (size_t c = 0; c < bins_used.size(); ++c) {
    if (bins_used[c] < 0 || bins_used[c] >= K)
      throw MeshError("bin " + std::to_string(bins_used[c]) + " is outside 0.." + std::to_string(K - 1));
    if (bits[c] != 1 && bits[c] != -1) throw MeshError("bits must be +1 or -1");
  }
  if (!(o.alpha > 0)) throw MeshError("alpha must be > 0");
  if (!(o.delta_k > 0 && o.delta_k < 1)) throw MeshError("delta_k must be in (0, 1)");
  if (!(o.guard >= 0 && o.guard < 0.25)) throw MeshError("guard must be in [0, 0.25)");
  if (!(o.k_max > 1)) throw MeshError("k_max must be > 1");
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  Workspace ws;
  OnceResult r;
  Eigen::Vector3d c = masked_centroid(V, mask);
  embed_once(V, mask, K, bins_used, bits, o, c, ws, r);
  Eigen::Vector3d c_marked = r.centroid;
  double drift = (c_marked - c).norm();
  ChoEmbedResult best;
  auto keep = [&]() {  // the buffers of r and best are swapped, not copied
    std::swap(best.V, r.V);
    best.k = r.k;
    best.failed = r.failed;
    best.n_moved = r.n_moved;
    best.evaluations = r.evaluations;
    best.center = c;
    best.drift = drift;
  };
  keep();
  int it = 0;
  // Re-synchronisation (docs/radial.md, not in the paper): re-embed the original about the centre
  // of the previous marked mesh; keep the iterate with the smallest drift.
  for (; it < o.center_iters && drift > 0; ++it) {
    c = c_marked;
    embed_once(V, mask, K, bins_used, bits, o, c, ws, r);
    c_marked = r.centroid;
    drift = (c_marked - c).norm();
    if (drift < best.drift) keep();
  }
  best.iterations = it;
  return best;
}

}  // namespace meshmark
