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
  double fine_best = at(t0, ids);
  for (int i = 0; i <= 50; ++i) {
    const double t = (t0 - 1e-3) + 2e-3 * i / 50.0;
    const double s = at(t, ids);
    if (s > fine_best) fine_best = s, best_t = t;
  }
  return fine_best > base + min_gain ? best_t : 1.0;
}

}  // namespace meshmark
