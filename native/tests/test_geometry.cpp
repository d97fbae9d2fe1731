// C++ unit tests of the geometric quantities: hand-computed answers.
#include "meshmark/angle_sum.h"
#include "meshmark/dihedral_angles.h"
#include "meshmark/face_areas.h"
#include "meshmark/face_normals.h"
#include "meshmark/interior_angles.h"
#include "meshmark/pca.h"

#include <gtest/gtest.h>
#include <cmath>

using namespace meshmark;

TEST(Geometry, RightTriangle) {
  MatrixX3dR V(3, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 1, 0;
  MatrixX3iR T(1, 3);
  T << 0, 1, 2;
  EXPECT_NEAR(face_areas(V, T)[0], 1.0, 1e-15);
  const MatrixX3dR N = face_normals(V, T);
  EXPECT_NEAR(N(0, 2), 1.0, 1e-15);
  const auto A = interior_angles(V, T);
  EXPECT_NEAR(A(0, 0), M_PI / 2, 1e-15);
  EXPECT_NEAR(A.row(0).sum(), M_PI, 1e-14);
  EXPECT_NEAR(A(0, 1), std::atan(0.5), 1e-15);
}

TEST(Geometry, DihedralOfAFoldedSquare) {
  MatrixX3dR V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1;  // fold along the 1-2 diagonal
  MatrixX3iR T(2, 3);
  T << 0, 1, 2, 1, 3, 2;
  const DihedralAngles D = dihedral_angles(V, T);
  int interior = 0;
  for (Eigen::Index e = 0; e < D.angle.size(); ++e) {
    if (std::isnan(D.angle[e])) continue;
    ++interior;
    // normals (0,0,1) and normalize((-1,-1,1)): cos = 1/sqrt(3)
    EXPECT_NEAR(D.angle[e], std::acos(1 / std::sqrt(3.0)), 1e-12);
  }
  EXPECT_EQ(interior, 1);
}

TEST(Geometry, AngleSumOfCubeCornerIsThreeHalfPi) {
  // Three faces of a cube meeting at the origin, each split in two triangles.
  MatrixX3dR V(7, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0, 0, 1, 1, 1, 0, 1;
  MatrixX3iR T(6, 3);
  T << 0, 2, 4, 0, 4, 1, 0, 1, 6, 0, 6, 3, 0, 3, 5, 0, 5, 2;
  EXPECT_NEAR(angle_sum(V, T)[0], 3 * M_PI / 2, 1e-12);
}

TEST(PCA, AxesSortedAndSkewPositive) {
  // Points on the x axis with a long positive tail, a little spread in y.
  MatrixX3dR V(6, 3);
  V << -1, 0, 0, -1, 0.1, 0, 0, 0, 0, 0, -0.1, 0, 1, 0, 0, 5, 0.05, 0;
  const PCA p = pca(V);
  EXPECT_GE(p.eigenvalues[0], p.eigenvalues[1]);
  EXPECT_GE(p.eigenvalues[1], p.eigenvalues[2]);
  EXPECT_GT(p.axes(0, 0), 0.99);  // q1 points to +x, where the tail is
  EXPECT_GE(p.skewness[0], 0);
  // Rotating the points by 180 degrees about z rotates the axis with them.
  MatrixX3dR W = V;
  W.col(0) *= -1;
  W.col(1) *= -1;
  const PCA q = pca(W);
  EXPECT_LT(q.axes(0, 0), -0.99);
}
