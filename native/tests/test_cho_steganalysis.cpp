// C++ unit tests of the §6.4 steganalyzer's building blocks: the bin means from the sorted norms
// against a pass over the vertices (the binning of cho_watermark.h), and the margin test's p-value
// against the binomial law written out.
#include "meshmark/cho_bin_means.h"
#include "meshmark/cho_margin_test.h"
#include "meshmark/cho_norms.h"
#include "meshmark/radial_distances.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace meshmark;

TEST(ChoBinMeans, SameBinsAsAPassOverTheVertices) {
  std::mt19937_64 g(7);
  std::normal_distribution<double> nd;
  MatrixX3dR V(3001, 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int j = 0; j < 3; ++j) V(i, j) = nd(g) * (j + 1);
  V.row(17) = V.row(5);  // a tie
  VectorXb mask = VectorXb::Ones(V.rows());
  mask[3] = 0;
  const ChoNorms s = cho_norms(V, mask);
  ASSERT_EQ(s.r.size(), 3000u - 2u);
  std::vector<double> mean, want_sum;
  std::vector<int> count, want_count;
  for (const int K : {1, 2, 7, 64, 500, 2999, 6000}) {
    cho_bin_means(s, K, mean, count);
    const double W = (s.hi - s.lo) / K;
    want_sum.assign(K, 0);
    want_count.assign(K, 0);
    for (const double x : s.r) {
      const int k = std::min(std::max(static_cast<int>((x - s.lo) / W), 0), K - 1);
      want_sum[k] += std::min(std::max((x - (s.lo + W * k)) / W, 0.0), 1.0);
      ++want_count[k];
    }
    for (int k = 0; k < K; ++k) {
      ASSERT_EQ(count[k], want_count[k]) << "K=" << K << " k=" << k;
      if (count[k]) EXPECT_NEAR(mean[k], want_sum[k] / count[k], 1e-12) << "K=" << K << " k=" << k;
    }
  }
}

TEST(ChoMarginTest, BinomialTailOfTheHole) {
  // 40 bin means 0.5 - 0.01, 0.5 + 0.01, 0.5 - 0.02, ...; the first has too few vertices, so the
  // |d| are 0.01, 0.02, 0.02, 0.03, ... and the 4th smallest is 0.03 (trim 3)
  std::vector<double> mean;
  std::vector<int> count;
  for (int i = 0; i < 40; ++i) {
    mean.push_back(0.5 + (i % 2 ? 1 : -1) * 0.01 * (i / 2 + 1));
    count.push_back(10);
  }
  count[0] = 4;  // below min_count: left out (d = -0.01)
  const ChoMarginTest t = cho_margin_test(mean, count, 3, 5, 8);
  ASSERT_TRUE(t.ok);
  EXPECT_EQ(t.n_bins, 39);
  EXPECT_EQ(t.n_above, 20);
  EXPECT_NEAR(t.hole, 0.03, 1e-15);
  const double h = t.hole;
  // the two null fits: centred normal with sigma = median |d| / 0.6745, and N(mean d, sd d)
  std::vector<double> d;
  for (int i = 1; i < 40; ++i) d.push_back(mean[i] - 0.5);
  std::vector<double> a(d.size());
  std::transform(d.begin(), d.end(), a.begin(), [](double x) { return std::abs(x); });
  std::sort(a.begin(), a.end());
  const double med = a[(a.size() - 1) / 2];
  double b = 0, ss = 0;
  for (double x : d) b += x;
  b /= d.size();
  for (double x : d) ss += (x - b) * (x - b);
  const double sd = std::sqrt(ss / d.size());
  auto Phi = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  const double q1 = 2 * Phi(h / (med / 0.6744897501960817)) - 1;
  const double q2 = Phi((h - b) / sd) - Phi((-h - b) / sd);
  const double q = std::min(q1, q2);
  EXPECT_NEAR(t.q, q, 1e-12);
  double p = 0;
  for (int i = 0; i <= 3; ++i) p += std::tgamma(40.0) / (std::tgamma(i + 1.0) * std::tgamma(40.0 - i)) *
                                  std::pow(q, i) * std::pow(1 - q, 39 - i);
  EXPECT_NEAR(t.log_p, std::log(p), 1e-9);
  // too few bins for trim 3 (needs 2 (trim + 1) = 8 and min_bins): no test
  EXPECT_FALSE(cho_margin_test(std::vector<double>(mean.begin(), mean.begin() + 6),
                               std::vector<int>(6, 10), 3, 5, 2).ok);
}
