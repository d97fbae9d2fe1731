#include "meshmark/face_areas.h"

#include <Eigen/Geometry>

namespace meshmark {

Eigen::VectorXd face_areas(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  Eigen::VectorXd A(T.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    A[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  return A;
}

}  // namespace meshmark
