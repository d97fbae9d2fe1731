// meshmark: the per-vector statistics of the steganalysis feature sets (thesis §8.1.4; docs/steganalysis.md).
#pragma once
#include <Eigen/Core>

namespace meshmark {

// The log floor of every feature set (docs/steganalysis.md §2, "Invariance"): 1e-7 in unit-cube units
// (lengths) and in radians (angles). Float32 mesh files resolve ~6e-8 of the bounding box, so smaller
// differences are storage noise, and the rounding of a transformed mesh's coordinates (~1e-15 of its
// size) then moves log(1e-7 + noise) by < 1e-8 per value. At the former 1e-12 the log-skewness and
// log-kurtosis of vectors with values near 1e-9..1e-11 moved by up to 1e-6 under a rotation.
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
// ceil(log2 n) + 1 when IQR == 0 < max - min. n < 2 -> 1. (fd_bins_exact: the same as a double,
// not truncated to int; capped at 2^52.)
double fd_bins_exact(const Eigen::Ref<const Eigen::VectorXd>& f);
int fd_bins(const Eigen::Ref<const Eigen::VectorXd>& f);

// The last four components: moments4 of log|n'|, n' the first differences of the counts of the H
// equal-width bins over [min f, max f] (numpy.histogram(f, H)); zero differences are left out (log 0).
// With far more bins than values the differences are taken from the occupied bins only (same result).
Eigen::Vector4d histogram_moments(const Eigen::Ref<const Eigen::VectorXd>& f);

}  // namespace meshmark
