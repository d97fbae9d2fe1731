#include "meshmark/cotangent_smooth.h"
#include "meshmark/error.h"
#include "meshmark/unique_edges.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace meshmark {

MatrixX3dR cotangent_smooth(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                            double lambda, int iterations, const VectorXi& fixed) {
  if (!std::isfinite(lambda)) throw MeshError("smoothing factor lambda must be finite");
  if (iterations < 0) throw MeshError("smoothing iterations must be >= 0, got " + std::to_string(iterations));
  const Index n = static_cast<Index>(V.rows());
  const Eigen::Index t = T.rows();
  // Unique edges of the triangles and, for each triangle side, its edge id.
  const EdgeList EL = unique_edges(n, Polygons::from_triangles(MatrixX3iR(T)));
  const MatrixX2iR& E = EL.E;
  std::vector<Offset> first(static_cast<size_t>(n) + 1, 0);  // edges are sorted by E(:,0)
  for (Eigen::Index e = 0; e < E.rows(); ++e) ++first[E(e, 0) + 1];
  for (Index i = 0; i < n; ++i) first[i + 1] += first[i];
  auto edge_id = [&](Index a, Index b) {
    if (a > b) std::swap(a, b);
    Offset l = first[a], h = first[a + 1];
    while (l < h) {  // binary search of b among the edges starting at a
      const Offset mid = (l + h) / 2;
      if (E(mid, 1) < b) l = mid + 1; else h = mid;
    }
    return l;
  };
  std::vector<Offset> side(static_cast<size_t>(3 * t));
  for (Eigen::Index f = 0; f < t; ++f)
    for (int k = 0; k < 3; ++k) side[3 * f + k] = edge_id(T(f, (k + 1) % 3), T(f, (k + 2) % 3));  // side opposite corner k

  std::vector<char> moves(static_cast<size_t>(n), 1);
  for (Eigen::Index k = 0; k < fixed.size(); ++k) moves[fixed[k]] = 0;
  std::vector<double> w(static_cast<size_t>(E.rows()));
  MatrixX3dR X = V;
  for (int it = 0; it < iterations; ++it) {
    std::fill(w.begin(), w.end(), 0.0);
    for (Eigen::Index f = 0; f < t; ++f) {
      for (int k = 0; k < 3; ++k) {  // cot of the angle at corner k, weight of the opposite edge
        const Eigen::Vector3d p = X.row(T(f, k)), a = X.row(T(f, (k + 1) % 3)), b = X.row(T(f, (k + 2) % 3));
        const Eigen::Vector3d e1 = a - p, e2 = b - p;
        const double cr = e1.cross(e2).norm();
        if (cr > 0) w[side[3 * f + k]] += 0.5 * e1.dot(e2) / cr;
      }
    }
    MatrixX3dR S = MatrixX3dR::Zero(n, 3), U = MatrixX3dR::Zero(n, 3);
    Eigen::VectorXd ws = Eigen::VectorXd::Zero(n), deg = Eigen::VectorXd::Zero(n);
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
      const Index a = E(e, 0), b = E(e, 1);
      const double we = std::max(0.0, w[e]);
      S.row(a) += we * X.row(b);
      S.row(b) += we * X.row(a);
      ws[a] += we;
      ws[b] += we;
      U.row(a) += X.row(b);
      U.row(b) += X.row(a);
      deg[a] += 1;
      deg[b] += 1;
    }
    MatrixX3dR Y = X;
    for (Index i = 0; i < n; ++i) {
      if (!moves[i] || deg[i] == 0) continue;
      const Eigen::RowVector3d target = ws[i] > 0 ? Eigen::RowVector3d(S.row(i) / ws[i]) : Eigen::RowVector3d(U.row(i) / deg[i]);
      Y.row(i) += lambda * (target - X.row(i));
    }
    X.swap(Y);
  }
  return X;
}

}  // namespace meshmark
