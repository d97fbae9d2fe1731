#include "meshmark/gaussian_curvature.h"
#include "meshmark/angle_sum.h"
#include "meshmark/unique_edges.h"

#include <cmath>

namespace meshmark {

GaussianCurvature gaussian_curvature(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index n = V.rows();
  GaussianCurvature out;
  const Eigen::VectorXd S = angle_sum(V, T);
  out.kappa = Eigen::VectorXd::Zero(n);
  out.interior = VectorXb::Zero(n);
  out.boundary = VectorXb::Zero(n);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.interior[T(f, k)] = 1;  // referenced
  const EdgeList edges = unique_edges(static_cast<Index>(n), Polygons::from_triangles(MatrixX3iR(T)));
  VectorXb nonmanifold = VectorXb::Zero(n);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    const int c = edges.face_count[e];
    if (c == 2) continue;
    for (int k = 0; k < 2; ++k) {
      const Index v = edges.E(e, k);
      out.interior[v] = 0;
      if (c == 1) out.boundary[v] = 1;
      else nonmanifold[v] = 1;
    }
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    if (!out.interior[v] && !out.boundary[v] && !nonmanifold[v]) continue;  // unreferenced
    out.kappa[v] = (out.boundary[v] && !nonmanifold[v] ? M_PI : 2 * M_PI) - S[v];  // eq. 5.1.1
  }
  return out;
}

}  // namespace meshmark
