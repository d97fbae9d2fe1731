#include "meshmark/face_normal_noise.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace meshmark {

Eigen::VectorXd face_normal_noise(const Eigen::Ref<const MatrixX3dR>& X, const Eigen::Ref<const MatrixX3iR>& T,
                                  const Eigen::Ref<const Eigen::VectorXd>& vertex_noise) {
  const bool unit = vertex_noise.size() == 0;
  Eigen::VectorXd nu(T.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::RowVector3d e1 = X.row(T(f, 1)) - X.row(T(f, 0)), e2 = X.row(T(f, 2)) - X.row(T(f, 0));
    const double c = e1.cross(e2).norm();
    double s = 1;
    if (!unit) s = std::max({vertex_noise[T(f, 0)], vertex_noise[T(f, 1)], vertex_noise[T(f, 2)]});
    nu[f] = c > 0 ? 2 * std::sqrt(3.0) * s * (e1.norm() + e2.norm() + (e2 - e1).norm()) / c : std::numeric_limits<double>::infinity();
  }
  return nu;
}

}  // namespace meshmark
