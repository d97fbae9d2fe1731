#include "meshmark/feature_statistics.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace meshmark {

namespace {

// Mean, unbiased variance and the biased central sums m2, m3, m4 (divided by n) of x, accumulated in
// long double (64-bit mantissa) and rounded once: the sums do not depend on the order of the elements
// (vertex / face numbering) to double precision (docs/steganalysis.md §2).
struct CentralMoments {
  long double mean = 0, var = 0, m2 = 0, m3 = 0, m4 = 0;
  Eigen::Index n = 0;
};

CentralMoments central_moments(const Eigen::Ref<const Eigen::VectorXd>& x) {
  using LD = long double;
  CentralMoments c;
  c.n = x.size();
  if (c.n == 0) return c;
  LD s = 0;
  for (Eigen::Index i = 0; i < c.n; ++i) s += x[i];
  c.mean = s / c.n;
  if (c.n == 1) return c;
  LD m2 = 0, m3 = 0, m4 = 0;
  for (Eigen::Index i = 0; i < c.n; ++i) {
    const LD d = x[i] - c.mean, d2 = d * d;
    m2 += d2;
    m3 += d2 * d;
    m4 += d2 * d2;
  }
  c.var = m2 / (c.n - 1);  // unbiased variance
  c.m2 = m2 / c.n, c.m3 = m3 / c.n, c.m4 = m4 / c.n;
  return c;
}

}  // namespace

Eigen::Vector4d moments4(const Eigen::Ref<const Eigen::VectorXd>& x) {
  const CentralMoments c = central_moments(x);
  Eigen::Vector4d out(static_cast<double>(c.mean), static_cast<double>(c.var), 0.0, 0.0);
  if (c.n > 1 && c.m2 > 0) {
    out[2] = static_cast<double>(c.m3 / (c.m2 * std::sqrt(c.m2)));  // biased skewness
    out[3] = static_cast<double>(c.m4 / (c.m2 * c.m2));             // biased, non-excess kurtosis
  }
  return out;
}

Eigen::Vector4d moments4_regularized(const Eigen::Ref<const Eigen::VectorXd>& x, double s0) {
  // moments4 with the variance floor s0 added to m2 in the skewness and kurtosis denominators
  const CentralMoments c = central_moments(x);
  Eigen::Vector4d out(static_cast<double>(c.mean), static_cast<double>(c.var), 0.0, 0.0);
  if (c.n > 1) {
    const long double r = c.m2 + static_cast<long double>(s0);
    out[2] = static_cast<double>(c.m3 / (r * std::sqrt(r)));
    out[3] = static_cast<double>(c.m4 / (r * r));
  }
  return out;
}

std::vector<double> floored_values(const NoisyVector& v, double cap) {
  std::vector<double> out;
  out.reserve(v.f.size());
  for (size_t i = 0; i < v.f.size(); ++i) {
    const double fl = kNoiseFactor * v.b[i];
    if (!(fl <= cap) || !std::isfinite(v.f[i])) continue;  // not determined by the geometry: left out
    out.push_back(std::max(std::abs(v.f[i]), fl));
  }
  return out;
}

Eigen::Vector4d floored_log_moments(const NoisyVector& v, double cap) {
  std::vector<double> y = floored_values(v, cap);
  for (double& x : y) x = std::log(x);
  return moments4_regularized(Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(y.size())));
}

Eigen::Vector4d log_moments(const Eigen::Ref<const Eigen::VectorXd>& f, double floor) {
  Eigen::VectorXd y(f.size());
  if (floor > 0)
    for (Eigen::Index i = 0; i < f.size(); ++i) y[i] = std::log(std::max(std::abs(f[i]), floor));
  else
    for (Eigen::Index i = 0; i < f.size(); ++i) y[i] = std::log(std::abs(f[i]) - floor);
  return moments4(y);
}

namespace {
constexpr double kMaxBins = 4503599627370496.0;  // 2^52: bin indices stay exact in double
// Linearly interpolated quantile q of the sorted-in-place scratch s (numpy 'linear', type 7).
double quantile(std::vector<double>& s, double q) {
  const double pos = q * static_cast<double>(s.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  std::nth_element(s.begin(), s.begin() + lo, s.end());
  const double a = s[lo];
  if (lo + 1 >= s.size()) return a;
  const double b = *std::min_element(s.begin() + lo + 1, s.end());
  return a + (pos - static_cast<double>(lo)) * (b - a);
}
}  // namespace

double fd_bins_exact(const Eigen::Ref<const Eigen::VectorXd>& f) {
  const Eigen::Index n = f.size();
  if (n < 2) return 1;
  const double lo = f.minCoeff(), hi = f.maxCoeff(), range = hi - lo;
  if (!(range > 0)) return 1;
  std::vector<double> s(f.data(), f.data() + n);
  const double q1 = quantile(s, 0.25), q3 = quantile(s, 0.75), iqr = q3 - q1;
  double H;
  if (iqr > kHistogramSnap * range) {
    const double h = 2.0 * iqr / std::cbrt(static_cast<double>(n));  // eq. 8.1.4
    H = std::ceil(range / h - kHistogramSnap);                       // eq. 8.1.3 (snapped)
  } else {
    H = std::ceil(std::log2(static_cast<double>(n))) + 1;  // Sturges: zero IQR (docs/steganalysis.md)
  }
  return std::min(std::max(H, 1.0), kMaxBins);
}

int fd_bins(const Eigen::Ref<const Eigen::VectorXd>& f) { return static_cast<int>(fd_bins_exact(f)); }

Eigen::Vector4d histogram_moments(const Eigen::Ref<const Eigen::VectorXd>& f) {
  const double Hd = fd_bins_exact(f);
  if (Hd < 2) return Eigen::Vector4d::Zero();
  const long H = static_cast<long>(Hd);
  const Eigen::Index n = f.size();
  const double lo = f.minCoeff(), hi = f.maxCoeff(), scale = Hd / (hi - lo);
  auto bin = [&](double x) {  // numpy.histogram: equal bins over [lo, hi], the last one closed
    const long k = static_cast<long>((x - lo) * scale + kHistogramSnap);
    return std::min(std::max(k, 0L), H - 1);
  };
  std::vector<double> d;  // log|n'| of the non-zero first differences of the counts
  if (H <= 4 * static_cast<long>(n) + 64) {  // dense counts
    std::vector<long> cnt(H, 0);
    for (Eigen::Index i = 0; i < n; ++i) ++cnt[bin(f[i])];
    d.reserve(H - 1);
    for (long k = 1; k < H; ++k)
      if (cnt[k] != cnt[k - 1]) d.push_back(std::log(std::abs(static_cast<double>(cnt[k] - cnt[k - 1]))));
  } else {  // sparse: far more bins than values (heavy tail); the same differences from the occupied bins
    std::vector<long> b(n);
    for (Eigen::Index i = 0; i < n; ++i) b[i] = bin(f[i]);
    std::sort(b.begin(), b.end());
    long prev_bin = -1, prev_cnt = 0;
    for (size_t i = 0; i < b.size();) {
      size_t j = i;
      while (j < b.size() && b[j] == b[i]) ++j;
      const long k = b[i], c = static_cast<long>(j - i);
      if (prev_bin >= 0) {
        if (k == prev_bin + 1) {
          if (c != prev_cnt) d.push_back(std::log(std::abs(static_cast<double>(c - prev_cnt))));
        } else {  // prev_cnt -> 0 after the occupied bin, 0 -> c before this one; zeros in between
          d.push_back(std::log(static_cast<double>(prev_cnt)));
          d.push_back(std::log(static_cast<double>(c)));
        }
      }
      prev_bin = k, prev_cnt = c;
      i = j;
    }
  }
  return moments4(Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size())));
}

}  // namespace meshmark
