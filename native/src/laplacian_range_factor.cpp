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

// std::lower_bound(d, d + n, x), found from a nearby index p (any p in [0, n]): galloping from p
// towards x (1, 2, 4, ... elements), then a binary search in the last step. The answer does not
// depend on p; the cost is about 2 log2 of the distance, all in cache when the distance is small.
inline size_t lower_bound_near(const double* d, size_t n, double x, size_t p) {
  // the usual case: a few elements forward (the factors ascend), stepped over one by one
  for (int s = 0; s < 8; ++s) {
    if (p == n || !(d[p] < x)) {
      if (p == 0 || d[p - 1] < x) return p;  // d[p - 1] < x <= d[p]: the answer
      break;
    }
    ++p;
  }
  if (p < n && d[p] < x) {  // the answer is > p
    size_t lo = p + 1, step = 1;
    while (lo + step <= n && d[lo + step - 1] < x) lo += step, step *= 2;
    const size_t hi = std::min(n, lo + step);  // d[lo - 1] < x, and d[hi - 1] >= x or hi == n
    return static_cast<size_t>(std::lower_bound(d + lo, d + hi, x) - d);
  }
  // the answer is <= p: d[p] >= x (or p == n)
  size_t hi = p, step = 1;
  while (hi >= step && !(d[hi - step] < x)) hi -= step, step *= 2;
  const size_t lo = hi >= step ? hi - step : 0;  // d[lo] < x (or lo == 0), d[hi] >= x (or hi == n)
  return static_cast<size_t>(std::lower_bound(d + lo, d + hi, x) - d);
}

// score() * |ids| for every factor in `ts` (the coarse grid or the fine one), the same sums in the
// same order as score() adds them (carrier by carrier), so the result is bit-identical. Each bin
// edge's position is searched from its position at the previous factor (ts[1..] ascend, so the edge
// moves little from one to the next) instead of through the whole index for every edge and factor
// (bench/carrier_bench.py: this scan is what grows with the number of carriers).
std::vector<double> scan_scores(const SortedIndex& idx, double lo, double hi, int K, const std::vector<long long>& ids,
                                const std::vector<double>& ts) {
  const size_t nt = ts.size();
  std::vector<double> sums(nt, 0.0), delta(nt), lot(nt);
  for (size_t i = 0; i < nt; ++i) lot[i] = lo * ts[i], delta[i] = (hi * ts[i] - lo * ts[i]) / K;  // as score()
  std::vector<size_t> n(3 * nt);
  for (long long j : ids) {
    const double k0 = static_cast<double>(2 * j + 1);
    for (int e = 0; e < 3; ++e) {
      const double k = k0 + e;
      size_t p = 0;
      for (size_t i = 0; i < nt; ++i) {
        const double x = lot[i] + delta[i] * k;  // eq. 7.1.7's bin edge for the range (t lo, t hi)
        p = i < 2 ? idx.lower_bound(x) : lower_bound_near(idx.d, idx.n, x, p);
        n[3 * i + e] = p;
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
  std::vector<double> tc(202);
  tc[0] = 1.0;
  for (int i = 0; i <= 200; ++i) tc[i + 1] = (1 - span) + (2 * span) * i / 200.0;
  const std::vector<double> coarse = scan_scores(idx, lo, hi, K, coarse_ids, tc);
  const double n_c = static_cast<double>(coarse_ids.size());  // at(t, coarse_ids) = coarse[.] / n_c
  double best_t = 1.0, best = coarse[0] / n_c;
  for (int i = 0; i <= 200; ++i) {
    const double s = coarse[i + 1] / n_c;
    if (s > best) best = s, best_t = tc[i + 1];
  }
  // fine, with every carrier: the best, then 51 values within +-1e-3 of it
  const double t0 = best_t;
  std::vector<double> ts(52);
  ts[0] = t0;
  for (int i = 0; i <= 50; ++i) ts[i + 1] = (t0 - 1e-3) + 2e-3 * i / 50.0;
  const std::vector<double> sums = scan_scores(idx, lo, hi, K, ids, ts);
  double fine_best = sums[0] / static_cast<double>(ids.size());
  for (int i = 0; i <= 50; ++i) {
    const double s = sums[i + 1] / static_cast<double>(ids.size());
    if (s > fine_best) fine_best = s, best_t = ts[i + 1];
  }
  return fine_best > base + min_gain ? best_t : 1.0;
}

}  // namespace meshmark
