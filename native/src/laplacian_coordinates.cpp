#include "meshmark/laplacian_coordinates.h"

namespace meshmark {

MatrixX3dR laplacian_coordinates(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, double eps) {
  const Eigen::Index n = V.rows();
  MatrixX3dR L(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Offset b = A.ptr[i], e = A.ptr[i + 1];
    double x = 0, y = 0, z = 0;
    for (Offset k = b; k < e; ++k) {
      const Index j = A.nbr[k];
      x += V(j, 0);
      y += V(j, 1);
      z += V(j, 2);
    }
    const double deg = static_cast<double>(e - b) - eps;  // eqs. 7.1.2-7.1.4
    L(i, 0) = deg * V(i, 0) - x;
    L(i, 1) = deg * V(i, 1) - y;
    L(i, 2) = deg * V(i, 2) - z;
  }
  return L;
}

Eigen::VectorXd laplacian_lengths(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, double eps) {
  return laplacian_coordinates(V, A, eps).rowwise().norm();  // eq. 7.1.5
}

}  // namespace meshmark
