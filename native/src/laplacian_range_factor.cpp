#include "meshmark/laplacian_range_factor.h"

#include <algorithm>
#include <cmath>

namespace meshmark {

namespace {

// Index of the first element >= x in d[from:], by galloping forward from `from` (the edges of one
// range are visited in ascending order, so each search starts where the last one ended).
size_t gallop(const Eigen::Ref<const Eigen::VectorXd>& d, size_t from, double x) {
  size_t step = 1, lo = from, hi = from;
  while (hi < static_cast<size_t>(d.size()) && d[hi] < x) {
    lo = hi + 1;
    hi = from + step;
    step *= 2;
  }
  hi = std::min(hi, static_cast<size_t>(d.size()));
  return static_cast<size_t>(std::lower_bound(d.data() + lo, d.data() + hi, x) - d.data());
}

// Mean relative margin of the carrier pairs for the range (lo, hi); `sorted_ids` ascending.
double score(const Eigen::Ref<const Eigen::VectorXd>& d, double lo, double hi, int K, const std::vector<long long>& sorted_ids) {
  const double delta = (hi - lo) / K;  // eq. 7.1.7
  size_t pos = 0;
  double s = 0;
  for (long long j : sorted_ids) {
    const double k = static_cast<double>(2 * j + 1);
    const size_t n0 = gallop(d, pos, lo + delta * k);
    const size_t n1 = gallop(d, n0, lo + delta * (k + 1));
    const size_t n2 = gallop(d, n1, lo + delta * (k + 2));
    const double a = static_cast<double>(n1 - n0), b = static_cast<double>(n2 - n1);
    s += std::abs(a - b) / std::max(a + b, 1.0);
    pos = n0;
  }
  return s / static_cast<double>(sorted_ids.size());
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
  std::vector<long long> sorted_ids(ids);
  std::sort(sorted_ids.begin(), sorted_ids.end());
  auto at = [&](double t) { return score(d, lo * t, hi * t, K, sorted_ids); };
  const double base = at(1.0);
  // coarse: t = 1, then 201 values over [1 - span, 1 + span] (numpy.linspace); the first best wins
  double best_t = 1.0, best = base;
  for (int i = 0; i <= 200; ++i) {
    const double t = (1 - span) + (2 * span) * i / 200.0;
    const double s = at(t);
    if (s > best) best = s, best_t = t;
  }
  // fine: the best, then 51 values within +-1e-3 of it
  double t0 = best_t, fine_best = best;
  for (int i = 0; i <= 50; ++i) {
    const double t = (t0 - 1e-3) + 2e-3 * i / 50.0;
    const double s = at(t);
    if (s > fine_best) fine_best = s, best_t = t;
  }
  return fine_best > base + min_gain ? best_t : 1.0;
}

}  // namespace meshmark
