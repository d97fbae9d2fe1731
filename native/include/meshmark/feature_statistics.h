// meshmark: the per-vector statistics of the steganalysis feature sets (thesis §8.1.4; docs/steganalysis.md).
#pragma once
#include <Eigen/Core>

namespace meshmark {

#include <vector>

// The stabilised sets (YANG208, LFS76s, NVT36s; docs/steganalysis.md §2, "Invariance") floor each value
// at a multiple of its own storage noise: every element carries a first-order bound b of how far it can
// move when every vertex coordinate (unit-cube frame) moves by kStorageUnit = 2^-24, float32's unit
// roundoff, and the value used is max(|f|, kNoiseFactor * b). A difference a float32 file cannot
// resolve is then exactly its floor, so neither storage rounding nor the ~1e-16 rounding of a
// transformed mesh moves it; an element whose floor exceeds its set's cap (a sliver's normal, an
// azimuth on the axis, a curvature ratio at a flat vertex) carries no information and is left out.
constexpr double kStorageUnit = 0x1p-24;
constexpr double kNoiseFactor = 10.0;
// Variance floor of the standardised log-moments: skewness m3 / (m2 + s0)^1.5, kurtosis m4 / (m2 + s0)^2.
// Continuous where all values coincide (m2 -> 0), unlike the 0-by-convention rule; it changes the two
// statistics by a relative 2 s0 / m2 (< 1e-5 for the log-variances of real vectors, 0.1 ... 50).
constexpr double kMomentVarianceFloor = 1e-6;
// Histograms: an IQR below 1e-9 of the range counts as 0 (Sturges), and a value within 1e-9 of a bin
// width below an edge, or a bin count within 1e-9 below an integer, goes up: exact coincidences of
// regular (CAD, grid) meshes then fall on one side under any rounding.
constexpr double kHistogramSnap = 1e-9;

// The values and noise bounds of one feature vector of a stabilised set.
struct NoisyVector {
  std::vector<double> f, b;  // value, first-order bound of its change per kStorageUnit of vertex noise
  void push(double value, double bound) { f.push_back(value), b.push_back(bound); }
  void reserve(size_t n) { f.reserve(n), b.reserve(n); }
};

// max(|f|, kNoiseFactor b) of the elements with kNoiseFactor b <= cap (finite): the floored values.
std::vector<double> floored_values(const NoisyVector& v, double cap);
// moments4_regularized of log(floored_values) (the first four components of a stabilised block).
Eigen::Vector4d floored_log_moments(const NoisyVector& v, double cap);
// Mean, variance (N - 1), and the regularised skewness and kurtosis (kMomentVarianceFloor); empty -> 0,
// one value -> (x, 0, 0, 0).
Eigen::Vector4d moments4_regularized(const Eigen::Ref<const Eigen::VectorXd>& x, double s0 = kMomentVarianceFloor);

// The log floor of the published-style log(|f| + eps) forms (kept for the feature_log_moments binding).
constexpr double kFeatureLogFloor = 1e-7;

// Mean, variance (N - 1), skewness and kurtosis (both biased, kurtosis non-excess: MATLAB's
// skewness/kurtosis defaults) of the sample x. Conventions (docs/steganalysis.md §2):
//   empty sample -> (0, 0, 0, 0); one value -> (x, 0, 0, 0); zero variance -> skewness = kurtosis = 0.
Eigen::Vector4d moments4(const Eigen::Ref<const Eigen::VectorXd>& x);

// The first four components of eq. 8.1.4's block: moments4 of log(max(|f|, floor)) (floor > 0 keeps
// exact zeros and rounding noise finite; YANG208 uses kFeatureLogFloor). With floor <= 0,
// log(|f| + eps) is used instead, eps = -floor (the LFS76/NVT36 form; published eps = 2^-52, here kFeatureLogFloor).
Eigen::Vector4d log_moments(const Eigen::Ref<const Eigen::VectorXd>& f, double floor);

// The number of Freedman-Diaconis bins of eqs. 8.1.3-8.1.4: H = ceil((max - min) / h), h = 2 IQR / n^(1/3)
// (IQR from linearly interpolated quartiles, numpy's default). H = 1 when max == min; Sturges'
// ceil(log2 n) + 1 when IQR <= kHistogramSnap (max - min). n < 2 -> 1. (fd_bins_exact: the same as a
// double, not truncated to int; capped at 2^52.) The ceiling snaps: a ratio within kHistogramSnap above
// an integer gives that integer.
double fd_bins_exact(const Eigen::Ref<const Eigen::VectorXd>& f);
int fd_bins(const Eigen::Ref<const Eigen::VectorXd>& f);

// The last four components: moments4 of log|n'|, n' the first differences of the counts of the H
// equal-width bins over [min f, max f] (numpy.histogram(f, H), except that a value within kHistogramSnap
// of a bin width below an edge counts in the upper bin); zero differences are left out (log 0).
// With far more bins than values the differences are taken from the occupied bins only (same result).
Eigen::Vector4d histogram_moments(const Eigen::Ref<const Eigen::VectorXd>& f);

}  // namespace meshmark
