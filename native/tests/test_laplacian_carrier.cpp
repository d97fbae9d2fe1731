// C++ tests of laplacian_carrier.h: analytic values on the icosahedron, and the two overloads (edge
// list for extraction, adjacency for the embedding's rounds) agree on an irregular mesh.
#include "meshmark/error.h"
#include "meshmark/laplacian_carrier.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace meshmark;

namespace {
void icosahedron(MatrixX3dR& V, MatrixX3iR& T) {
  const double p = (1 + std::sqrt(5.0)) / 2;
  V.resize(12, 3);
  V << -1, p, 0, 1, p, 0, -1, -p, 0, 1, -p, 0, 0, -1, p, 0, 1, p, 0, -1, -p, 0, 1, -p, p, 0, -1, p, 0, 1, -p, 0, -1,
      -p, 0, 1;
  V /= V.row(0).norm();
  T.resize(20, 3);
  T << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4,
      2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1;
}
}  // namespace

TEST(LaplacianCarrier, IcosahedronAnalytic) {
  MatrixX3dR V;
  MatrixX3iR T;
  icosahedron(V, T);
  const MatrixX2iR E = unique_edges(12, Polygons::from_triangles(T)).E;
  const double a = std::sqrt(2 - 2 / std::sqrt(5.0)), lap = 5 * (1 - 1 / std::sqrt(5.0));
  const double area = 5.0 / 3.0 * std::sqrt(3.0) / 4 * a * a;
  const double expect[6] = {lap / 2.0, lap / a, lap / a, lap / std::sqrt(3.0) * a / area,
                            lap / std::sqrt(3.0) * a / area, lap / 2.0};
  for (int k = 0; k < 6; ++k) {
    const auto F = laplacian_carrier(V, E, T, static_cast<LaplacianCarrier>(k), 2.0, true);
    for (int i = 0; i < 12; ++i) {
      EXPECT_NEAR(F.value[i], expect[k], 1e-12) << "kind " << k;
      EXPECT_NEAR(F.direction.row(i).dot(V.row(i)), 1.0, 1e-12) << "kind " << k;  // outward, unit
    }
  }
}

TEST(LaplacianCarrier, EdgeAndAdjacencyOverloadsAgree) {
  MatrixX3dR V;
  MatrixX3iR T;
  icosahedron(V, T);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int c = 0; c < 3; ++c) V(i, c) += u(rng);
  const MatrixX2iR E = unique_edges(12, Polygons::from_triangles(T)).E;
  const Adjacency A = vertex_adjacency(12, E);
  for (int k = 0; k < 6; ++k) {
    const auto kind = static_cast<LaplacianCarrier>(k);
    const auto Fe = laplacian_carrier(V, E, T, kind, 0.7, true, k == 2 ? 0.1 : 0.0);
    const auto Fa = laplacian_carrier(V, A, T, kind, 0.7, true, k == 2 ? 0.1 : 0.0);
    for (int i = 0; i < 12; ++i) {
      EXPECT_NEAR(Fe.value[i], Fa.value[i], 1e-12 * (1 + std::abs(Fe.value[i]))) << "kind " << k;
      EXPECT_NEAR(Fe.gain[i], Fa.gain[i], 1e-12 * (1 + std::abs(Fe.gain[i]))) << "kind " << k;
    }
  }
}

namespace {
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }  // -0 != +0, NaN == NaN
}  // namespace

// The embedding's fast path for the default carrier (laplacian_local_ring / laplacian_local_change)
// against the general adjacency overload it replaces there, bit for bit (signed zeros included): a
// triangulated grid, partly flat (L_i = 0, so no direction) and partly jittered, an isolated vertex,
// neighbour lists in sorted and in shuffled order (the embedding's breadth-first renumbering leaves
// them unsorted), targets above and below the values.
TEST(LaplacianCarrier, LocalRingIsBitIdenticalToTheGeneralPath) {
  const int g = 30;
  const Index n = g * g + 1;  // + one vertex without edges
  MatrixX3dR V = MatrixX3dR::Zero(n, 3);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int r = 0; r < g; ++r)
    for (int c = 0; c < g; ++c) {
      const Index i = r * g + c;
      V(i, 0) = c, V(i, 1) = r;
      if (r >= g / 2) V(i, 0) += u(rng), V(i, 1) += u(rng), V(i, 2) = u(rng);  // the lower half stays flat
    }
  V(n - 1, 0) = 100;
  std::vector<Index> tri;
  for (int r = 0; r + 1 < g; ++r)
    for (int c = 0; c + 1 < g; ++c) {
      const Index a = r * g + c, b = a + 1, d = a + g, e = d + 1;
      tri.insert(tri.end(), {a, b, e, a, e, d});
    }
  MatrixX3iR T = Eigen::Map<MatrixX3iR>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  const MatrixX2iR E = unique_edges(n, Polygons::from_triangles(T)).E;
  Adjacency A = vertex_adjacency(n, E);
  const MatrixX3iR none(0, 3);
  LocalRingCarrier R;  // reused: the second pass overwrites the first's storage
  for (int shuffled = 0; shuffled < 2; ++shuffled) {
    if (shuffled)
      for (Index i = 0; i < n; ++i) std::shuffle(A.nbr.data() + A.ptr[i], A.nbr.data() + A.ptr[i + 1], rng);
    const LaplacianCarrierField F = laplacian_carrier(V, A, none, LaplacianCarrier::Local, 1.0, true);
    LocalRingCarrier Rb;  // the branch-free variant: the same values
    laplacian_local_ring(V, A, Rb, true);
    laplacian_local_ring(V, A, R);
    Eigen::VectorXd dt = F.value;
    std::uniform_real_distribution<double> p(0, 1);
    int zero_dir = 0;
    for (Index i = 0; i < n; ++i) {
      ASSERT_TRUE(same_bits(R.value[i], F.value[i])) << "vertex " << i << (shuffled ? " (shuffled lists)" : "");
      ASSERT_TRUE(same_bits(Rb.value[i], F.value[i]) && same_bits(Rb.ell[i], R.ell[i])) << "branch-free, vertex " << i;
      if (p(rng) < 0.3 || i == n - 1) dt[i] = F.value[i] + u(rng);
      zero_dir += dt[i] != F.value[i] && F.gain[i] == 0;
    }
    EXPECT_GT(zero_dir, 5);  // moved vertices without a direction (flat part, isolated vertex) are covered
    MatrixX3dR dL = MatrixX3dR::Constant(n, 3, 7.0);  // overwritten
    laplacian_local_change(V, A, R, dt, dL);
    for (Index i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        // carrier_change in laplacian_watermark.cpp: direction_i (gain_i (d^_i - d_i)), 0 where unmoved
        const double want = dt[i] != F.value[i] ? F.direction(i, c) * (F.gain[i] * (dt[i] - F.value[i])) : 0.0;
        ASSERT_TRUE(same_bits(dL(i, c), want)) << "vertex " << i << " component " << c;
      }
  }
}

// The edge-list overload (the extraction's scalar) against the plain scatter loop it must equal bit for
// bit (its speed-ups must not change the sums): edges sorted as unique_edges lists them, shuffled, and
// with a loop edge and a repeated edge.
TEST(LaplacianCarrier, EdgeListIsBitIdenticalToThePlainScatter) {
  MatrixX3dR V;
  MatrixX3iR T;
  icosahedron(V, T);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int c = 0; c < 3; ++c) V(i, c) += u(rng);
  const MatrixX2iR sorted = unique_edges(12, Polygons::from_triangles(T)).E;
  auto plain = [&](const MatrixX2iR& E) {
    MatrixX3dR L = MatrixX3dR::Zero(12, 3);
    Eigen::VectorXd len = Eigen::VectorXd::Zero(12), out = Eigen::VectorXd::Zero(12);
    std::vector<int> deg(12, 0);
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
      const Index a = E(e, 0), b = E(e, 1);
      const double x = V(a, 0) - V(b, 0), y = V(a, 1) - V(b, 1), z = V(a, 2) - V(b, 2);
      const double l = std::sqrt(x * x + y * y + z * z);
      L(a, 0) += x, L(a, 1) += y, L(a, 2) += z, len[a] += l;
      L(b, 0) -= x, L(b, 1) -= y, L(b, 2) -= z, len[b] += l;
      ++deg[a], ++deg[b];
    }
    for (int i = 0; i < 12; ++i) {
      if (deg[i] == 0) continue;
      const double ell = len[i] / deg[i];
      if (ell > 0) out[i] = Eigen::RowVector3d(L(i, 0), L(i, 1), L(i, 2)).norm() / ell;
    }
    return out;
  };
  MatrixX2iR shuffled = sorted;
  std::vector<Eigen::Index> perm(sorted.rows());
  for (size_t k = 0; k < perm.size(); ++k) perm[k] = static_cast<Eigen::Index>(k);
  std::shuffle(perm.begin(), perm.end(), rng);
  for (size_t k = 0; k < perm.size(); ++k) shuffled.row(static_cast<Eigen::Index>(k)) = sorted.row(perm[k]);
  MatrixX2iR odd(sorted.rows() + 2, 2);
  odd << sorted.topRows(5), Eigen::RowVector2i(4, 4), sorted.row(3), sorted.bottomRows(sorted.rows() - 5);
  const MatrixX3iR none(0, 3);
  for (const MatrixX2iR* E : std::vector<const MatrixX2iR*>{&sorted, &shuffled, &odd}) {
    const Eigen::VectorXd want = plain(*E);
    const Eigen::VectorXd got = laplacian_carrier(V, *E, none, LaplacianCarrier::Local).value;
    for (int i = 0; i < 12; ++i) EXPECT_TRUE(same_bits(got[i], want[i])) << "vertex " << i;
  }
}

TEST(LaplacianCarrier, BadInputIsAnError) {
  MatrixX3dR V;
  MatrixX3iR T;
  icosahedron(V, T);
  const MatrixX2iR E = unique_edges(12, Polygons::from_triangles(T)).E;
  const MatrixX3iR none(0, 3);
  EXPECT_THROW(laplacian_carrier(V, E, none, LaplacianCarrier::Normal), MeshError);
  EXPECT_THROW(laplacian_carrier(V, E, T, static_cast<LaplacianCarrier>(9)), MeshError);
  EXPECT_THROW(laplacian_carrier(V, E, T, LaplacianCarrier::Thesis, 0.0), MeshError);
  EXPECT_NO_THROW(laplacian_carrier(V, E, none, LaplacianCarrier::Local));
}
