// C++ unit tests of the steganalysis statistics and the edge-face map: hand-computed answers.
#include "meshmark/edge_faces.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"
#include "meshmark/yang208_features.h"
#include "meshmark/error.h"

#include <gtest/gtest.h>
#include <cmath>

using namespace meshmark;

TEST(Steganalysis, MomentsByHand) {
  Eigen::VectorXd x(4);
  x << 1, 2, 3, 10;  // mean 4, deviations -3 -2 -1 6
  const Eigen::Vector4d m = moments4(x);
  EXPECT_DOUBLE_EQ(m[0], 4.0);
  EXPECT_NEAR(m[1], (9 + 4 + 1 + 36) / 3.0, 1e-14);
  const double m2 = 50 / 4.0, m3 = (-27 - 8 - 1 + 216) / 4.0, m4 = (81 + 16 + 1 + 1296) / 4.0;
  EXPECT_NEAR(m[2], m3 / std::pow(m2, 1.5), 1e-14);
  EXPECT_NEAR(m[3], m4 / (m2 * m2), 1e-14);
}

TEST(Steganalysis, HistogramOfTwoClusters) {
  Eigen::VectorXd x(8);
  x << 0, 0, 0, 0, 1, 1, 1, 1;  // IQR = 1, h = 2 / 2 = 1, H = 1: no n'
  EXPECT_EQ(fd_bins(x), 1);
  EXPECT_EQ(histogram_moments(x), Eigen::Vector4d::Zero());
}

TEST(Steganalysis, EdgeFacesOfTwoTriangles) {
  MatrixX3iR T(2, 3);
  T << 0, 1, 2, 2, 1, 3;
  const EdgeList E = unique_edges(4, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(4, E.E);
  const EdgeFaces F = edge_faces(E, A, T);
  for (Eigen::Index e = 0; e < E.E.rows(); ++e) {
    const bool shared = E.E(e, 0) == 1 && E.E(e, 1) == 2;
    EXPECT_EQ(F.f1[e] >= 0, shared);
    if (shared) EXPECT_EQ(F.f0[e] + F.f1[e], 1);
  }
}

TEST(Steganalysis, TooSmall) {
  MatrixX3dR V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  MatrixX3iR T(1, 3);
  T << 0, 1, 2;
  EXPECT_THROW(yang208_features(V, T), MeshError);
}
