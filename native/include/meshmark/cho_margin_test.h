// meshmark: the margin test of one bin number K, the per-K statistic of the default decision rule of
// the §6.4 steganalyzer (not in the thesis; docs/radial.md §3.2).
//
// Cho's mean method moves the mean m_k of every bin (eq. 6.4.13) to at least 1/2 + alpha or at most
// 1/2 - alpha, so read with the embedding K no bin mean lies near 1/2. For a clean mesh the bin means
// d_k = m_k - 1/2 of the n bins holding at least min_count vertices are modelled as independent draws
// of a density that is continuous at 0; with h the (trim + 1)-th smallest |d_k|, the p-value of "no
// more than trim bins closer to 1/2 than h" is
//   p = P(Binomial(n, q) <= trim),   q = P(|d| < h)
// under the null fitted two ways, a centred normal whose median |d| is the observed one and the
// normal of the observed mean and standard deviation of d; the smaller q (the larger, more
// conservative p) is used. n < max(min_bins, 2 (trim + 1)): no test (ok = false).
#pragma once

#include <vector>

namespace meshmark {

struct ChoMarginTest {
  bool ok = false;
  double log_p = 0;  // natural log of p (0 when there is no evidence, e.g. h = 0)
  double hole = 0;   // h
  double q = 0;      // null probability of a bin mean within h of 1/2
  int n_bins = 0;    // n
  int n_above = 0;   // bins with m_k > 1/2 among them (the bits 1 of a Cho mark)
};

ChoMarginTest cho_margin_test(const std::vector<double>& mean, const std::vector<int>& count, int trim,
                              int min_count, int min_bins);

}  // namespace meshmark
