#include "meshmark/vertex_normals.h"

#include <Eigen/Geometry>

namespace meshmark {

MatrixX3dR vertex_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  MatrixX3dR N = MatrixX3dR::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) N.row(T(f, k)) += n;
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

}  // namespace meshmark
