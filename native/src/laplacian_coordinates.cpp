#include "meshmark/laplacian_coordinates.h"

#include <cmath>

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

Eigen::VectorXd laplacian_lengths(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX2iR>& E,
                                  double eps, double* mean_edge_length) {
  const Eigen::Index n = V.rows();
  MatrixX3dR L = -eps * V;  // eq. 7.1.4's -eps x_i
  double total = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {  // eq. 7.1.2: sum over N(i) of (x_i - x_j)
    const Index a = E(e, 0), b = E(e, 1);
    const double x = V(a, 0) - V(b, 0), y = V(a, 1) - V(b, 1), z = V(a, 2) - V(b, 2);
    L(a, 0) += x, L(a, 1) += y, L(a, 2) += z;
    L(b, 0) -= x, L(b, 1) -= y, L(b, 2) -= z;
    if (mean_edge_length) total += std::sqrt(x * x + y * y + z * z);
  }
  if (mean_edge_length) *mean_edge_length = E.rows() ? total / static_cast<double>(E.rows()) : 0.0;
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 0; i < n; ++i) d[i] = L.row(i).norm();  // eq. 7.1.5
  return d;
}

}  // namespace meshmark
