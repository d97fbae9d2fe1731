// C++ unit tests of the radial watermarks' building blocks: the vectorised exp/ln against std::exp
// and std::log, the masked PCA against the PCA of the selected rows, and the radial origin's
// counting selection against a plain sort.
#include "meshmark/pca.h"
#include "meshmark/radial_watermark.h"
#include "meshmark/vector_math.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace meshmark;

namespace {
double ulps(double got, double want) {
  if (got == want) return 0;
  const double u = std::nextafter(std::abs(want), std::numeric_limits<double>::infinity()) - std::abs(want);
  return std::abs(got - want) / u;
}
}  // namespace

TEST(VectorMath, ExpWithinOneUlp) {
  std::mt19937_64 g(1);
  std::uniform_real_distribution<double> u(-700.0, 0.0), v(-1.0, 1.0);
  std::vector<double> l(20000), out(l.size());
  for (size_t i = 0; i < l.size(); ++i) l[i] = i % 2 ? u(g) : v(g);
  double worst = 0;
  for (const double k : {0.001, 0.37, 1.0, 2.5, 100.0}) {
    exp_scaled(l.data(), k, out.data(), l.size());
    for (size_t i = 0; i < l.size(); ++i)
      if (k * l[i] > -708) worst = std::max(worst, ulps(out[i], std::exp(k * l[i])));
  }
  EXPECT_LE(worst, 1.0);
  const double special[] = {-std::numeric_limits<double>::infinity(), -800.0, 0.0};
  double res[3];
  exp_scaled(special, 1.0, res, 3);  // 0^k = 0; below -708 -> 0; e^0 = 1
  EXPECT_EQ(res[0], 0.0);
  EXPECT_EQ(res[1], 0.0);
  EXPECT_EQ(res[2], 1.0);
}

TEST(VectorMath, LogWithinTwoUlp) {
  std::mt19937_64 g(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> x(20000);
  for (size_t i = 0; i < x.size(); ++i) x[i] = i % 3 ? u(g) : std::pow(u(g), 40.0);
  x[0] = 0.0;
  x[1] = 1.0;
  x[2] = 5e-324;  // subnormal
  x[3] = 0.5;
  std::vector<double> y = x;
  log_inplace(y.data(), y.size());
  EXPECT_EQ(y[0], -std::numeric_limits<double>::infinity());
  EXPECT_EQ(y[1], 0.0);
  double worst = 0;
  for (size_t i = 2; i < x.size(); ++i) worst = std::max(worst, ulps(y[i], std::log(x[i])));
  EXPECT_LE(worst, 2.0);
}

TEST(VectorMath, LogMomentSumsXpLnX) {
  std::vector<double> x = {0.0, 0.25, 0.5, 1.0, 0.75, 1e-300, 0.125, 0.9, 0.3, 0.6, 0.01};  // n = 11: blocks + tail
  for (const int p : {1, 2}) {
    std::vector<double> y = x;
    double want = 0;
    for (const double v : x)
      if (v > 0) want += std::pow(v, p) * std::log(v);
    const double got = log_inplace_moment(y.data(), y.size(), p);
    EXPECT_NEAR(got, want, 1e-14);
    for (size_t i = 0; i < x.size(); ++i)
      if (x[i] > 0) EXPECT_LE(ulps(y[i], std::log(x[i])), 2.0);
    EXPECT_EQ(y[0], -std::numeric_limits<double>::infinity());
  }
}

TEST(PCA, MaskedEqualsSubset) {
  std::mt19937_64 g(3);
  std::normal_distribution<double> n(0.0, 1.0);
  MatrixX3dR V(500, 3);
  VectorXb mask(500);
  for (int i = 0; i < 500; ++i) {
    V.row(i) << 1e4 + 3 * n(g), -2e4 + n(g) + 0.2 * n(g) * n(g), 0.3 * n(g);  // skewed, far from 0
    mask[i] = i % 3 != 0;
  }
  MatrixX3dR W(mask.cast<int>().sum(), 3);
  for (int i = 0, r = 0; i < 500; ++i)
    if (mask[i]) W.row(r++) = V.row(i);
  const PCA a = pca(V, mask), b = pca(W);
  EXPECT_LT((a.centroid - b.centroid).norm(), 1e-9);
  EXPECT_LT((a.axes - b.axes).norm(), 1e-9);  // same axes with the same signs
  EXPECT_LT((a.eigenvalues - b.eigenvalues).norm(), 1e-9 * b.eigenvalues[0]);
  EXPECT_GT(a.skewness[0], 0);
}

TEST(RadialOrigin, CountingSelectionEqualsSort) {
  // The mean projection of the floor(N/2) largest projections (§6.1.1) against a plain sort, for both
  // orientations of the axis (the sign rule flips it for the mirrored cloud) and odd N.
  std::mt19937_64 g(4);
  std::exponential_distribution<double> e(1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  for (const double mirror : {1.0, -1.0}) {
    MatrixX3dR V(10001, 3);
    for (int i = 0; i < V.rows(); ++i) V.row(i) << mirror * 4 * e(g), n(g), 0.5 * n(g);
    VectorXb mask = VectorXb::Ones(V.rows());
    const RadialOrigin o = radial_origin(V, mask, RadialOriginMode::Axis);
    const PCA p = pca(V);
    EXPECT_LT((o.axis - p.axes.col(0)).norm(), 1e-12);
    std::vector<double> proj(V.rows());
    for (int i = 0; i < V.rows(); ++i) proj[i] = (V.row(i).transpose() - p.centroid).dot(p.axes.col(0));
    std::sort(proj.begin(), proj.end());
    const size_t h = proj.size() / 2;
    double s = 0;
    for (size_t i = proj.size() - h; i < proj.size(); ++i) s += proj[i];
    const Eigen::Vector3d want = p.centroid + (s / h) * p.axes.col(0);
    EXPECT_LT((o.origin - want).norm(), 1e-10) << "mirror " << mirror;
    EXPECT_GT(o.axis[0] * mirror, 0.9);  // the long tail is on the positive side
  }
}
