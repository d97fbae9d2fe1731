#include "meshmark/cho_margin_test.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshmark {

namespace {

// log P(Binomial(n, q) <= t) in log space (t is small: a sum of t + 1 terms).
double binomial_log_cdf(int t, int n, double q) {
  if (t >= n || q <= 0) return 0.0;
  if (q >= 1) return -std::numeric_limits<double>::infinity();
  const double lq = std::log(q), l1q = std::log1p(-q), lgn = std::lgamma(n + 1.0);
  double mx = -std::numeric_limits<double>::infinity();
  std::vector<double> terms(t + 1);
  for (int i = 0; i <= t; ++i) {
    terms[i] = lgn - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) + i * lq + (n - i) * l1q;
    mx = std::max(mx, terms[i]);
  }
  double sum = 0;
  for (const double x : terms) sum += std::exp(x - mx);
  return std::min(0.0, mx + std::log(sum));
}

// P(|Z| < h) for Z ~ N(b, sd^2)
double normal_within(double h, double b, double sd) {
  if (!(sd > 0)) return std::abs(b) < h ? 1.0 : 0.0;
  const double s = sd * std::sqrt(2.0);
  return std::max(0.0, 0.5 * (std::erfc((b - h) / s) - std::erfc((b + h) / s)));
}

}  // namespace

ChoMarginTest cho_margin_test(const std::vector<double>& mean, const std::vector<int>& count, int trim,
                              int min_count, int min_bins) {
  ChoMarginTest out;
  std::vector<double> d, a;
  d.reserve(mean.size());
  for (size_t k = 0; k < mean.size(); ++k)
    if (count[k] >= std::max(min_count, 1)) d.push_back(mean[k] - 0.5);  // eq. 6.4.13 minus 1/2
  const int n = static_cast<int>(d.size());
  out.n_bins = n;
  if (n < std::max(min_bins, 2 * (trim + 1))) return out;
  out.ok = true;
  double sum = 0;
  a.resize(d.size());
  for (int i = 0; i < n; ++i) {
    a[i] = std::abs(d[i]);
    sum += d[i];
    out.n_above += d[i] > 0;
  }
  const double b = sum / n;
  double ss = 0;
  for (const double x : d) ss += (x - b) * (x - b);
  const double sd = std::sqrt(ss / n);
  std::nth_element(a.begin(), a.begin() + trim, a.end());
  out.hole = a[trim];
  std::nth_element(a.begin() + trim, a.begin() + (n - 1) / 2, a.end());  // trim <= (n - 1) / 2
  const double med = a[(n - 1) / 2];
  if (!(out.hole > 0)) return out;  // a bin mean at 1/2 itself: no evidence
  // the centred normal with median |d| = med has sigma = med / Phi^-1(3/4)
  const double q1 = normal_within(out.hole, 0.0, med / 0.6744897501960817);
  const double q2 = normal_within(out.hole, b, sd);
  out.q = std::min(q1, q2);
  out.log_p = binomial_log_cdf(trim, n, out.q);
  return out;
}

}  // namespace meshmark
