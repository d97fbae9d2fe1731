#include "meshmark/interior_angles.h"

#include <Eigen/Geometry>
#include <cmath>

namespace meshmark {

Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> interior_angles(
    const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> A(T.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = V.row(T(f, k));
      const Eigen::Vector3d a = Eigen::Vector3d(V.row(T(f, (k + 1) % 3))) - p;
      const Eigen::Vector3d b = Eigen::Vector3d(V.row(T(f, (k + 2) % 3))) - p;
      A(f, k) = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
  return A;
}

}  // namespace meshmark
