#include "meshmark/cho_watermark.h"
#include "meshmark/error.h"
#include "meshmark/radial_distances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace meshmark {

ChoBins cho_bins(const Eigen::Ref<const Eigen::VectorXd>& rho, int K, const Eigen::Ref<const VectorXb>& mask) {
  if (K < 1) throw MeshError("the number of bins K must be at least 1, got " + std::to_string(K));
  if (mask.size() != rho.size()) throw MeshError("mask and rho differ in length");
  const Eigen::Index n = rho.size();
  Eigen::Index m = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  Eigen::Index i_lo = -1, i_hi = -1;  // the two reference vertices: the first vertex at rho_min / rho_max
  for (Eigen::Index i = 0; i < n; ++i)
    if (mask[i]) {
      ++m;
      if (rho[i] < lo) lo = rho[i], i_lo = i;
      if (rho[i] > hi) hi = rho[i], i_hi = i;
    }
  if (m < K)
    throw MeshError("the mesh has " + std::to_string(m) + " vertices but " + std::to_string(K) +
                    " bins were asked for: fewer vertices than bins");
  if (!(hi - lo > 1e-10 * hi))  // equal up to rounding
    throw MeshError("all " + std::to_string(m) + " vertices are at the same distance from the centre: "
                    "the vertex-norm histogram has no range");
  ChoBins b;
  b.K = K;
  b.rho_min = lo;
  b.rho_max = hi;
  b.width = (hi - lo) / K;  // Cho step 2: W = (rho_max - rho_min) / N
  b.bin = VectorXi::Constant(n, -1);
  b.x = Eigen::VectorXd::Zero(n);
  b.counts = VectorXi::Zero(K);
  for (Eigen::Index i = 0; i < n; ++i) {
    // Cho's strict inequalities leave the reference vertices out of every bin. Only one vertex at each
    // extreme is left out: other vertices tied with it (mirror-symmetric models) stay in the end bins
    // at x = 0 or 1, so a rounding that breaks the tie (rotation, float32) changes no bin.
    if (!mask[i] || i == i_lo || i == i_hi) continue;
    int k = static_cast<int>(std::floor((rho[i] - lo) / b.width));
    k = std::min(std::max(k, 0), K - 1);
    const double x = (rho[i] - (lo + b.width * k)) / b.width;  // Cho step 3: bin-range normalisation
    b.bin[i] = k;
    b.x[i] = std::min(std::max(x, 0.0), 1.0);
    ++b.counts[k];
  }
  return b;
}

Eigen::VectorXd cho_statistics(const ChoBins& bins, ChoMethod method) {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(bins.K);
  for (Eigen::Index i = 0; i < bins.bin.size(); ++i) {
    const int k = bins.bin[i];
    if (k < 0) continue;
    const double x = bins.x[i];
    s[k] += method == ChoMethod::Mean ? x : (2 * x - 1) * (2 * x - 1);
  }
  for (int k = 0; k < bins.K; ++k) s[k] /= std::max(bins.counts[k], 1);
  return s;
}

namespace {

// Histogram mapping (Cho step 4, Figs. 2.4-2.5) of one normalised value x with exponent k, given
// l = ln x (mean) or ln|2x-1| (variance): x' = x^k, or 2x'-1 = sgn(y)|y|^k with y = 2x-1.
double cho_map(double x, double l, double k, ChoMethod method, double guard) {
  const double a = l == -std::numeric_limits<double>::infinity() ? 0.0 : std::exp(k * l);  // x^k or |y|^k
  double xm;
  if (method == ChoMethod::Mean) {
    xm = a;
  } else {
    const double y = 2 * x - 1;
    xm = std::min(std::max(0.5 * ((y < 0 ? -a : (y > 0 ? a : 0.0)) + 1), 0.0), 1.0);
  }
  if (guard > 0 && k != 1.0) xm = std::min(std::max(xm, guard), 1 - guard);
  return xm;
}

// Statistic of one bin for exponent k from l = ln x (mean) or l = ln|2x-1| (variance), and its
// derivative in k. guard applies only when k != 1 (see cho_map).
double bin_stat(const double* l, int n, double k, ChoMethod method, double guard, double& dsdk) {
  double s = 0, d = 0;
  const bool g = guard > 0 && k != 1.0;
  if (method == ChoMethod::Mean) {
    for (int j = 0; j < n; ++j) {
      if (l[j] == -std::numeric_limits<double>::infinity()) {  // x = 0
        s += g ? guard : 0.0;
        continue;
      }
      const double v = std::exp(k * l[j]);  // x^k
      if (g && v < guard) s += guard;
      else if (g && v > 1 - guard) s += 1 - guard;
      else {
        s += v;
        d += l[j] * v;
      }
    }
  } else {
    const double cap = 1 - 2 * guard;
    for (int j = 0; j < n; ++j) {
      if (l[j] == -std::numeric_limits<double>::infinity()) continue;  // y = 0
      const double a = std::exp(k * l[j]);  // |y|^k
      if (g && a > cap) s += cap * cap;
      else {
        s += a * a;  // y'^2 = |y|^(2k)
        d += 2 * l[j] * a * a;
      }
    }
  }
  dsdk = d / n;
  return s / n;
}

struct OnceResult {
  MatrixX3dR V;
  int evaluations = 0;
  Eigen::VectorXd k;
  std::vector<int> failed;
  int n_moved = 0;
};

OnceResult embed_once(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                      const std::vector<int>& bins_used, const std::vector<int>& bits, const ChoEmbedOptions& o,
                      const Eigen::Vector3d& c) {
  const Eigen::VectorXd rho = radial_distances(V, mask, c);  // Cho step 1
  const ChoBins b = cho_bins(rho, K, mask);                  // Cho steps 2-3
  const Eigen::Index n = rho.size();
  // group the vertices by bin (counting sort), with l = ln x or ln|2x-1| laid out contiguously
  std::vector<Index> start(K + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i)
    if (b.bin[i] >= 0) ++start[b.bin[i] + 1];
  for (int k = 0; k < K; ++k) start[k + 1] += start[k];
  std::vector<Index> fill(start.begin(), start.end() - 1), member(start[K]);
  std::vector<double> l(start[K]);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int k = b.bin[i];
    if (k < 0) continue;
    const double x = b.x[i];
    member[fill[k]] = static_cast<Index>(i);
    l[fill[k]++] = std::log(o.method == ChoMethod::Mean ? x : std::abs(2 * x - 1));
  }
  const double ref = o.method == ChoMethod::Mean ? 0.5 : 1.0 / 3.0;
  OnceResult out;
  out.k = Eigen::VectorXd::Ones(K);
  const long m_up = std::lround((o.k_max - 1.0) / o.delta_k);  // k = 1 + m dk <= k_max   (w = -1)
  const long m_dn = std::lround((1.0 - o.delta_k) / o.delta_k);  // k = 1 - m dk >= dk      (w = +1)
  for (size_t c2 = 0; c2 < bins_used.size(); ++c2) {
    const int bin = bins_used[c2], w = bits[c2];
    const double* lb = l.data() + start[bin];
    const int cnt = start[bin + 1] - start[bin];
    const long m_hi = w > 0 ? m_dn : m_up;
    const double target = w > 0 ? ref + o.alpha : ref - o.alpha;
    auto k_of = [&](long m) { return w > 0 ? 1.0 - m * o.delta_k : 1.0 + m * o.delta_k; };
    // h(m) >= 0  <=>  the condition of Cho step 4 holds; h increases with m
    auto h = [&](long m, double& dhdm) {
      ++out.evaluations;
      double dsdk = 0;
      const double s = cnt ? bin_stat(lb, cnt, k_of(m), o.method, o.guard, dsdk) : 0.0;
      dhdm = -dsdk * o.delta_k;  // w=+1: h = S - t, dk/dm = -dk;  w=-1: h = t - S, dk/dm = +dk
      return w > 0 ? s - target : target - s;
    };
    double d0, dhi;
    const double h0 = h(0, d0);
    if (h0 >= 0 && cnt > 0) continue;  // already on the right side: k = 1, bin untouched
    if (cnt == 0) {
      out.failed.push_back(bin);
      out.k[bin] = h0 >= 0 ? 1.0 : k_of(m_hi);
      continue;
    }
    // The first step m with h(m) >= 0 (= the sequential search of Cho step 4), found by a
    // safeguarded Newton iteration on integer m inside the bracket h(lo) < 0 <= h(hi); h(m_hi) is
    // only evaluated when no smaller step satisfies the condition.
    long lo = 0, hi = m_hi;
    double guess = d0 > 0 ? -h0 / d0 : 0.5 * (lo + hi);
    for (int it = 0; hi - lo > 1; ++it) {
      if (!(guess > lo && guess < hi) || it >= 24) guess = 0.5 * (lo + hi);
      const long cand = std::min(std::max(std::lround(guess), lo + 1), hi - 1);
      double dh;
      const double hc = h(cand, dh);
      if (hc >= 0) hi = cand;
      else lo = cand;
      guess = dh > 0 ? cand - hc / dh : 0.5 * (lo + hi);
    }
    if (hi == m_hi && h(m_hi, dhi) < 0) out.failed.push_back(bin);  // the limit k = dk or k_max is not enough
    out.k[bin] = k_of(hi);
  }
  // Cho step 5: map, denormalise with the same bin range, move radially (theta, phi kept).
  Eigen::VectorXd rho_new = rho;
  for (int k = 0; k < K; ++k) {
    if (out.k[k] == 1.0) continue;
    const double kk = out.k[k];
    for (Index j = start[k]; j < start[k + 1]; ++j) {
      const Index i = member[j];
      rho_new[i] = b.rho_min + b.width * (k + cho_map(b.x[i], l[j], kk, o.method, o.guard));
      out.n_moved += rho_new[i] != rho[i];
    }
  }
  out.V = radial_rescale(V, c, rho, rho_new);
  return out;
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
  Eigen::Vector3d c = masked_centroid(V, mask);
  OnceResult r = embed_once(V, mask, K, bins_used, bits, o, c);
  double drift = (masked_centroid(r.V, mask) - c).norm();
  ChoEmbedResult best;
  auto keep = [&]() {
    best.V = r.V;
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
    c = masked_centroid(r.V, mask);
    r = embed_once(V, mask, K, bins_used, bits, o, c);
    drift = (masked_centroid(r.V, mask) - c).norm();
    if (drift < best.drift) keep();
  }
  best.iterations = it;
  return best;
}

}  // namespace meshmark
