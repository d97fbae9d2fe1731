// C++ unit tests of the ch. 3-5 analysis: analytic answers.
#include "meshmark/angle_sum.h"
#include "meshmark/curvature_degradation.h"
#include "meshmark/error.h"
#include "meshmark/gaussian_curvature.h"
#include "meshmark/normal_angle_expectation.h"
#include "meshmark/normal_degradation_sweep.h"
#include "meshmark/quantization_level.h"

#include <gtest/gtest.h>
#include <cmath>

using namespace meshmark;

TEST(Analysis, ExpectedAngleTangentAndTable41) {
  EXPECT_NEAR(expected_normal_angle(1e-8) / 1e-8, 0.5, 1e-12);          // E'(0) = 1/2 (eq. 4.1.9)
  EXPECT_NEAR(expected_normal_angle(0.5) - 0.25, 0.0092193064054, 1e-12);  // Table 4.1, mpmath value
  EXPECT_NEAR(expected_normal_angle(1.0), expected_normal_angle(1.0 - 1e-9), 1e-8);  // r = 1 limit
  EXPECT_NEAR(expected_normal_angle(1.0), expected_normal_angle(1.0 + 1e-9), 1e-8);
  EXPECT_THROW(expected_normal_angle(-1), MeshError);
}

TEST(Analysis, TetrahedronCurvatureAndLevels) {
  MatrixX3dR V(4, 3);
  V << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  MatrixX3iR T(4, 3);
  T << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  const GaussianCurvature g = gaussian_curvature(V, T);
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(g.kappa[v], M_PI, 1e-12);  // 2 pi - 3 * pi / 3
    EXPECT_EQ(g.interior[v], 1);
  }
  // equilateral faces of side a = 2 sqrt 2: h = a sqrt(3)/2 in every direction; the cube L = 2
  const double a = 2 * std::sqrt(2.0), h = a * std::sqrt(3.0) / 2, eps = 0.01;
  const QuantizationLevel q = quantization_level(V, T, eps, NoiseBound::Appr, LevelFormula::Linear, 0.608);
  // eq. 4.3.21 with 1 / rho = 3 / h in units of L
  EXPECT_EQ(q.level, static_cast<int>(std::ceil(-2 - std::log2(eps / (0.608 * 3 * 2 / h)))));
  EXPECT_THROW(quantization_level(V, T, 0.0, NoiseBound::Appr, LevelFormula::Auto, 0.608), MeshError);
}

TEST(Analysis, CurvatureDegradationVanishesWithoutDisplacement) {
  MatrixX3dR V(7, 3);
  V.row(0) << 0, 0, 1;
  for (int k = 0; k < 6; ++k) V.row(1 + k) << std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0;
  MatrixX3iR T(6, 3);
  for (int k = 0; k < 6; ++k) T.row(k) << 0, 1 + k, 1 + (k + 1) % 6;
  VectorXb moved = VectorXb::Zero(7), measured = VectorXb::Zero(7);
  moved[0] = measured[0] = 1;
  VectorXi t(2);
  t << 1, 1074;  // 2^-1073: below every coordinate's ulp, the apex does not move
  const Eigen::VectorXd k = curvature_degradation(V, T, t, Displacement::Normal, moved, measured, 1.0, 3, 5);
  EXPECT_GT(k[0], 1e-3);
  EXPECT_EQ(k[1], 0.0);
  // the fast angle sums agree with angle_sum: the apex curvature 2 pi - 6 angle
  const Eigen::VectorXd S = angle_sum(V, T);
  EXPECT_NEAR(gaussian_curvature(V, T).kappa[0], 2 * M_PI - S[0], 1e-15);
}

TEST(Analysis, SweepSeedsDiffer) {
  EXPECT_NE(sweep_seed(0, 12, 0), sweep_seed(0, 16, 0));
  EXPECT_NE(sweep_seed(0, 12, 0), sweep_seed(0, 12, 1));
  EXPECT_NE(sweep_seed(0, 12, 0), sweep_seed(1, 12, 0));
}

TEST(Analysis, LevelFastPathsEqualTheGeneralOnes) {
  // a bumpy grid with skinny, degenerate and unused parts: the fast paths give the general levels
  const int m = 40;
  MatrixX3dR V((m + 1) * (m + 1) + 1, 3);
  for (int i = 0; i <= m; ++i)
    for (int j = 0; j <= m; ++j)
      V.row(i * (m + 1) + j) << i * (i % 7 == 0 ? 1.0 : 1.3), j * 0.01 * (1 + j % 3), std::sin(0.3 * i * j);
  V.row(V.rows() - 1) << 5, 5, 5;  // unreferenced
  MatrixX3iR T(2 * m * m + 1, 3);
  int f = 0;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int a = i * (m + 1) + j;
      T.row(f++) << a, a + 1, a + m + 2;
      T.row(f++) << a, a + m + 2, a + m + 1;
    }
  T.row(f) << 0, 0, 1;  // zero area
  const Eigen::VectorXd kappa = gaussian_curvature(V, T).kappa;
  for (double eps : {0.001, 0.01, 0.1, 1.0}) {
    const auto fast = uniform_adaptive_levels(V, T, eps, 0.608);
    ASSERT_TRUE(fast.has_value());
    EXPECT_EQ(*fast, adaptive_levels(V, T, kappa, eps, 0.0, 0.0, 0.5, 0.608).vertex_level);
    for (NoiseBound b : {NoiseBound::Min, NoiseBound::Appr, NoiseBound::Max})
      for (LevelFormula fm : {LevelFormula::Auto, LevelFormula::Linear, LevelFormula::Exact}) {
        const auto only = quantization_level_only(V, T, eps, b, fm, 0.608);
        ASSERT_TRUE(only.has_value());
        EXPECT_EQ(*only, quantization_level(V, T, eps, b, fm, 0.608).level);
      }
  }
  MatrixX3dR Vh = V * 1e125;  // |x| >= 2^400: the curvature could overflow, the fast path defers
  EXPECT_FALSE(uniform_adaptive_levels(Vh, T, 0.01, 0.608).has_value());
}
