// C++ test of laplacian_range_factor.h: the range search equals the plain scan it replaces (every
// score a full lower_bound over the sorted lengths: coarse 201 factors on at most 256 carriers, fine
// 51 factors within +-1e-3 with every carrier), bit for bit, on skewed random histograms rescaled
// by known factors.
#include "meshmark/laplacian_range_factor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace meshmark;

namespace {
double score(const std::vector<double>& d, double lo, double hi, int K, const std::vector<long long>& ids) {
  const double delta = (hi - lo) / K;
  double s = 0;
  for (long long j : ids) {
    const double k = static_cast<double>(2 * j + 1);
    const auto n0 = std::lower_bound(d.begin(), d.end(), lo + delta * k);
    const auto n1 = std::lower_bound(d.begin(), d.end(), lo + delta * (k + 1));
    const auto n2 = std::lower_bound(d.begin(), d.end(), lo + delta * (k + 2));
    const double a = static_cast<double>(n1 - n0), b = static_cast<double>(n2 - n1);
    s += std::abs(a - b) / std::max(a + b, 1.0);
  }
  return s / static_cast<double>(ids.size());
}

double plain_range_factor(const std::vector<double>& d, double lo, double hi, int K, const std::vector<long long>& ids,
                          double span, double min_gain) {
  auto at = [&](double t, const std::vector<long long>& w) { return score(d, lo * t, hi * t, K, w); };
  std::vector<long long> sorted_ids(ids);
  std::sort(sorted_ids.begin(), sorted_ids.end());
  std::vector<long long> coarse;
  const size_t n_coarse = std::min<size_t>(256, sorted_ids.size());
  for (size_t i = 0; i < n_coarse; ++i) coarse.push_back(sorted_ids[i * sorted_ids.size() / n_coarse]);
  const double base = at(1.0, ids);
  double best_t = 1.0, best = at(1.0, coarse);
  for (int i = 0; i <= 200; ++i) {
    const double t = (1 - span) + (2 * span) * i / 200.0;
    const double s = at(t, coarse);
    if (s > best) best = s, best_t = t;
  }
  const double t0 = best_t;
  double fine_best = at(t0, ids);
  for (int i = 0; i <= 50; ++i) {
    const double t = (t0 - 1e-3) + 2e-3 * i / 50.0;
    const double s = at(t, ids);
    if (s > fine_best) fine_best = s, best_t = t;
  }
  return fine_best > base + min_gain ? best_t : 1.0;
}
}  // namespace

TEST(LaplacianRangeFactor, EqualsThePlainScan) {
  std::mt19937 rng(17);
  std::lognormal_distribution<double> len(0.0, 0.6);
  std::uniform_real_distribution<double> f(0.93, 1.07);
  int found = 0;
  // trials 12-13: a 1.28M-vertex-like density (long stretches per bin edge in the fine scan)
  for (int trial = 0; trial < 14; ++trial) {
    const int n = trial < 12 ? 4000 + 1500 * trial : 400000 * (trial - 10), K = n / 70;
    std::vector<double> d(n);
    for (double& x : d) x = len(rng);
    std::sort(d.begin(), d.end());
    const double lo = d.front(), hi = d.back();
    // a "marked" histogram: in every carrier pair one bin loses half its lengths to the other
    std::vector<long long> ids;
    const double delta = (hi - lo) / K;
    for (long long j = 0; j < (K - 2) / 2; ++j) {
      const double k = 2.0 * j + 1;
      const auto a = std::lower_bound(d.begin(), d.end(), lo + delta * k), b = std::lower_bound(d.begin(), d.end(), lo + delta * (k + 1)),
                 c = std::lower_bound(d.begin(), d.end(), lo + delta * (k + 2));
      if (c - a < 20) continue;
      ids.push_back(j);
      const bool up = (j * 7 + trial) % 2;
      if (up)
        for (auto it = b; it < b + (c - b) / 2; ++it) *it = lo + delta * (k + 0.5);
      else
        for (auto it = b - (b - a) / 2; it < b; ++it) *it = lo + delta * (k + 1.5);
    }
    std::sort(d.begin(), d.end());
    const double t_true = trial % 3 ? f(rng) : 1.0;
    for (double& x : d) x *= t_true;
    const Eigen::Map<const Eigen::VectorXd> dv(d.data(), static_cast<Eigen::Index>(d.size()));
    const double got = laplacian_range_factor(dv, lo, hi, K, ids, 0.1, 0.05);
    EXPECT_EQ(got, plain_range_factor(d, lo, hi, K, ids, 0.1, 0.05)) << "trial " << trial;
    found += std::abs(got - t_true) < 2e-3;
  }
  EXPECT_GE(found, 8);  // the search recovers the rescaling (where the marked pairs show it)
}
