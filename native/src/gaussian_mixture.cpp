#include "meshmark/gaussian_mixture.h"
#include "meshmark/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace meshmark {

double bhattacharyya_distance(double m1, double v1, double m2, double v2) {
  const double s = 0.5 * (v1 + v2);  // eq. 6.4.14
  return 0.125 * (m2 - m1) * (m2 - m1) / s + 0.5 * std::log(s / std::sqrt(v1 * v2));
}

GaussianMixture2 gaussian_mixture_2(const std::vector<double>& x, double reg_covar, double tol, int max_iter) {
  const size_t n = x.size();
  GaussianMixture2 g;
  g.label = VectorXi::Zero(n);
  if (n < 2) return g;
  // optimal 2-means split of the sorted values (prefix sums of x and x^2)
  std::vector<double> s(x);
  std::sort(s.begin(), s.end());
  std::vector<double> c1(n + 1, 0), c2(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    c1[i + 1] = c1[i] + s[i];
    c2[i + 1] = c2[i] + s[i] * s[i];
  }
  double best = std::numeric_limits<double>::infinity(), thr = 0;
  for (size_t k = 1; k < n; ++k) {
    if (!(s[k - 1] < s[k])) continue;
    const double a = c2[k] - c1[k] * c1[k] / k;
    const double b = (c2[n] - c2[k]) - (c1[n] - c1[k]) * (c1[n] - c1[k]) / (n - k);
    if (a + b < best) {
      best = a + b;
      thr = 0.5 * (s[k - 1] + s[k]);
    }
  }
  if (!std::isfinite(best)) return g;
  g.ok = true;
  std::vector<double> r(n);  // responsibility of component 1 (component 0 gets 1 - r)
  for (size_t i = 0; i < n; ++i) r[i] = x[i] > thr ? 1.0 : 0.0;
  const double eps10 = 10 * std::numeric_limits<double>::epsilon();
  const double log2pi = std::log(2 * M_PI);
  auto m_step = [&]() {
    double nk[2] = {eps10, eps10}, sx[2] = {0, 0};
    for (size_t i = 0; i < n; ++i) {
      nk[0] += 1 - r[i];
      nk[1] += r[i];
      sx[0] += (1 - r[i]) * x[i];
      sx[1] += r[i] * x[i];
    }
    for (int k = 0; k < 2; ++k) g.mean[k] = sx[k] / nk[k];
    double sv[2] = {0, 0};
    for (size_t i = 0; i < n; ++i) {
      const double d0 = x[i] - g.mean[0], d1 = x[i] - g.mean[1];
      sv[0] += (1 - r[i]) * d0 * d0;
      sv[1] += r[i] * d1 * d1;
    }
    for (int k = 0; k < 2; ++k) {
      g.var[k] = sv[k] / nk[k] + reg_covar;
      g.weight[k] = nk[k] / (nk[0] + nk[1]);
    }
  };
  // E-step: responsibilities and the mean log-likelihood
  auto e_step = [&]() {
    double lw[2], lv[2];
    for (int k = 0; k < 2; ++k) {
      lw[k] = std::log(g.weight[k]);
      lv[k] = std::log(g.var[k]);
    }
    double total = 0;
    for (size_t i = 0; i < n; ++i) {
      double l[2];
      for (int k = 0; k < 2; ++k) {
        const double d = x[i] - g.mean[k];
        l[k] = lw[k] - 0.5 * (log2pi + lv[k] + d * d / g.var[k]);
      }
      const double mx = std::max(l[0], l[1]);
      const double lse = mx + std::log(std::exp(l[0] - mx) + std::exp(l[1] - mx));
      r[i] = std::exp(l[1] - lse);
      g.label[i] = l[1] > l[0] ? 1 : 0;
      total += lse;
    }
    return total / n;
  };
  m_step();  // initial parameters from the hard partition
  double lb = -std::numeric_limits<double>::infinity();
  for (int it = 1; it <= max_iter; ++it) {
    const double prev = lb;
    lb = e_step();
    m_step();
    g.n_iter = it;
    if (std::abs(lb - prev) < tol) {
      g.converged = true;
      break;
    }
  }
  g.lower_bound = lb;
  e_step();  // labels consistent with the final parameters (as sklearn's fit_predict)
  return g;
}

}  // namespace meshmark
