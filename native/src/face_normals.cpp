#include "meshmark/face_normals.h"

#include <Eigen/Geometry>

namespace meshmark {

MatrixX3dR face_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  MatrixX3dR N(T.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    N.row(f) = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  }
  return N;
}

}  // namespace meshmark
