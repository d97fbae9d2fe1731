#include "meshmark/laplacian_range_factor.h"

#include <algorithm>
#include <cmath>

namespace meshmark {

namespace {

// lower_bound over the sorted lengths through a table of bucket starts: the searches of the range
// scan fall into [x0, x1), cut into equal buckets, each holding a handful of lengths.
struct SortedIndex {
  const double* d;
  size_t n;
  double x0 = 0, inv_w = 0;
  std::vector<size_t> first;  // first[b] = #d < x0 + b w

  SortedIndex(const Eigen::Ref<const Eigen::VectorXd>& v, double lo, double hi) : d(v.data()), n(static_cast<size_t>(v.size())) {
    const size_t buckets = std::max<size_t>(1024, std::min<size_t>(4 * n, size_t(1) << 20));
    x0 = lo;
    const double w = (hi - lo) / static_cast<double>(buckets);
    inv_w = w > 0 ? 1.0 / w : 0.0;
    first.resize(buckets + 2);
    size_t i = 0;
    for (size_t b = 0; b <= buckets + 1; ++b) {
      const double x = x0 + static_cast<double>(b) * w;
      while (i < n && d[i] < x) ++i;
      first[b] = i;
    }
  }

  size_t lower_bound(double x) const {
    const double f = (x - x0) * inv_w;
    if (inv_w == 0 || !(f >= 0) || f >= static_cast<double>(first.size() - 1))
      return static_cast<size_t>(std::lower_bound(d, d + n, x) - d);
    const size_t b = static_cast<size_t>(f);
    // the bucket's range may be off by an ulp of the grid: widen by one bucket on each side
    const size_t s = first[b > 0 ? b - 1 : 0], e = first[std::min(b + 2, first.size() - 1)];
    return static_cast<size_t>(std::lower_bound(d + s, d + e, x) - d);
  }
};

// Mean relative margin of the carrier pairs for the range (lo, hi).
double score(const SortedIndex& idx, double lo, double hi, int K, const std::vector<long long>& ids) {
  const double delta = (hi - lo) / K;  // eq. 7.1.7
  double s = 0;
  for (long long j : ids) {
    const double k = static_cast<double>(2 * j + 1);
    const size_t n0 = idx.lower_bound(lo + delta * k);
    const size_t n1 = idx.lower_bound(lo + delta * (k + 1));
    const size_t n2 = idx.lower_bound(lo + delta * (k + 2));
    const double a = static_cast<double>(n1 - n0), b = static_cast<double>(n2 - n1);
    s += std::abs(a - b) / std::max(a + b, 1.0);
  }
  return s / static_cast<double>(ids.size());
}

// lower_bound of each of the ascending queries q[a, b) in d[s, f) (every answer known to lie in
// [s, f]): the middle query is searched first and splits the range for the others, so that the 51
// positions of one bin edge cost about 51 log2(stretch / 51) steps instead of 51 log2(stretch). The
// answers are those of std::lower_bound over [s, f): a query <= q[mid] has its answer <= p (d[p] >=
// q[mid]), one >= q[mid] its answer >= p (d[k] < q[mid] for k < p).
void sorted_lower_bounds(const double* d, size_t s, size_t f, const double* q, size_t a, size_t b, size_t* out) {
  while (a < b) {
    const size_t mid = a + (b - a) / 2;
    const size_t p = static_cast<size_t>(std::lower_bound(d + s, d + f, q[mid]) - d);
    out[mid] = p;
    sorted_lower_bounds(d, s, p, q, a, mid, out);
    s = p, a = mid + 1;  // the right half, iteratively
  }
}

// score() * |ids| for every factor in `ts` (all within a few 1e-3 of each other), the same sums in the
// same order as score() adds them, so the result is bit-identical. Each bin edge moves over a short
// stretch of the sorted lengths as t varies: that stretch is found once per edge (two lookups) and
// the edge's position for every t is searched inside it (in cache), instead of one lookup in the
// whole index per edge and t (the cost that grows with the carriers: bench/carrier_bench.py).
std::vector<double> fine_scores(const SortedIndex& idx, double lo, double hi, int K, const std::vector<long long>& ids,
                                const std::vector<double>& ts) {
  const size_t nt = ts.size();
  const double t_min = *std::min_element(ts.begin(), ts.end()), t_max = *std::max_element(ts.begin(), ts.end());
  std::vector<double> sums(nt, 0.0), delta(nt), lot(nt);
  for (size_t i = 0; i < nt; ++i) lot[i] = lo * ts[i], delta[i] = (hi * ts[i] - lo * ts[i]) / K;  // as score()
  auto edge = [&](size_t i, double k) { return lot[i] + delta[i] * k; };
  std::vector<size_t> n(3 * nt), pos(nt);
  std::vector<double> x(nt);
  for (long long j : ids) {
    const double k0 = static_cast<double>(2 * j + 1);
    for (int e = 0; e < 3; ++e) {
      const double k = k0 + e;
      // the edge's stretch over [t_min, t_max], widened against rounding
      const double a = lo * t_min + ((hi * t_min - lo * t_min) / K) * k, b = lo * t_max + ((hi * t_max - lo * t_max) / K) * k;
      const double w_lo = std::min(a, b), w_hi = std::max(a, b), pad = 1e-9 * (std::abs(w_lo) + std::abs(w_hi)) + 1e-300;
      const double x_lo = w_lo - pad, x_hi = w_hi + pad;
      const size_t s = idx.lower_bound(x_lo), f = idx.lower_bound(x_hi);
      // ts[1..] ascend (the fine grid); when the edge's positions x ascend with them and all lie in the
      // stretch (the usual case), search them together; otherwise one by one, as before.
      bool together = nt > 2;
      for (size_t i = 1; i < nt && together; ++i) {
        x[i] = edge(i, k);
        together = x[i] >= x_lo && x[i] <= x_hi && (i == 1 || x[i] >= x[i - 1]);
      }
      if (together) {
        sorted_lower_bounds(idx.d, s, f, x.data(), 1, nt, pos.data());
        for (size_t i = 1; i < nt; ++i) n[3 * i + e] = pos[i];
      }
      for (size_t i = 0; i < (together ? 1 : nt); ++i) {  // ts[0] (the coarse best), or every t
        const double xi = edge(i, k);
        n[3 * i + e] = (xi >= x_lo && xi <= x_hi) ? static_cast<size_t>(std::lower_bound(idx.d + s, idx.d + f, xi) - idx.d)
                                                  : idx.lower_bound(xi);
      }
    }
    for (size_t i = 0; i < nt; ++i) {
      const double c1 = static_cast<double>(n[3 * i + 1] - n[3 * i]), c2 = static_cast<double>(n[3 * i + 2] - n[3 * i + 1]);
      sums[i] += std::abs(c1 - c2) / std::max(c1 + c2, 1.0);
    }
  }
  return sums;
}

}  // namespace

void laplacian_pair_counts(const Eigen::Ref<const Eigen::VectorXd>& d, double lo, double hi, int K, const std::vector<long long>& ids,
                           std::vector<long long>& c1, std::vector<long long>& c2) {
  const double delta = (hi - lo) / K;  // eq. 7.1.7
  c1.resize(ids.size());
  c2.resize(ids.size());
  for (size_t c = 0; c < ids.size(); ++c) {
    const double k = static_cast<double>(2 * ids[c] + 1);
    const auto n0 = std::lower_bound(d.data(), d.data() + d.size(), lo + delta * k);
    const auto n1 = std::lower_bound(n0, d.data() + d.size(), lo + delta * (k + 1));
    const auto n2 = std::lower_bound(n1, d.data() + d.size(), lo + delta * (k + 2));
    c1[c] = n1 - n0;
    c2[c] = n2 - n1;
  }
}

double laplacian_range_factor(const Eigen::Ref<const Eigen::VectorXd>& d, double lo, double hi, int K,
                              const std::vector<long long>& ids, double span, double min_gain) {
  if (ids.empty()) return 1.0;
  // every edge searched lies in [lo (1 - span - 1e-3), hi (1 + span + 1e-3)]
  const SortedIndex idx(d, lo * (1 - span - 2e-3), hi * (1 + span + 2e-3));
  auto at = [&](double t, const std::vector<long long>& which) { return score(idx, lo * t, hi * t, K, which); };
  // The coarse scan scores at most 256 carriers, evenly spaced over the sorted list (all of them
  // below that): it only has to land within the fine scan's +-1e-3 of the best factor.
  std::vector<long long> sorted_ids(ids);
  std::sort(sorted_ids.begin(), sorted_ids.end());
  std::vector<long long> coarse_ids;
  const size_t n_coarse = std::min<size_t>(256, sorted_ids.size());
  for (size_t i = 0; i < n_coarse; ++i) coarse_ids.push_back(sorted_ids[i * sorted_ids.size() / n_coarse]);
  const double base = at(1.0, ids);
  // coarse: t = 1, then 201 values over [1 - span, 1 + span] (numpy.linspace); the first best wins
  double best_t = 1.0, best = at(1.0, coarse_ids);
  for (int i = 0; i <= 200; ++i) {
    const double t = (1 - span) + (2 * span) * i / 200.0;
    const double s = at(t, coarse_ids);
    if (s > best) best = s, best_t = t;
  }
  // fine, with every carrier: the best, then 51 values within +-1e-3 of it
  const double t0 = best_t;
  std::vector<double> ts(52);
  ts[0] = t0;
  for (int i = 0; i <= 50; ++i) ts[i + 1] = (t0 - 1e-3) + 2e-3 * i / 50.0;
  const std::vector<double> sums = fine_scores(idx, lo, hi, K, ids, ts);
  double fine_best = sums[0] / static_cast<double>(ids.size());
  for (int i = 0; i <= 50; ++i) {
    const double s = sums[i + 1] / static_cast<double>(ids.size());
    if (s > fine_best) fine_best = s, best_t = ts[i + 1];
  }
  return fine_best > base + min_gain ? best_t : 1.0;
}

}  // namespace meshmark
