#include "meshmark/kirchhoff_matrix.h"

#include <vector>

namespace meshmark {

Eigen::SparseMatrix<double> kirchhoff_matrix(Index n, const Eigen::Ref<const MatrixX2iR>& E, double eps) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(2 * E.rows() + n));
  Eigen::VectorXd deg = Eigen::VectorXd::Zero(n);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    t.emplace_back(E(e, 0), E(e, 1), -1.0);  // eq. 7.1.3: -1 for neighbours
    t.emplace_back(E(e, 1), E(e, 0), -1.0);
    deg[E(e, 0)] += 1;
    deg[E(e, 1)] += 1;
  }
  for (Index i = 0; i < n; ++i) t.emplace_back(i, i, deg[i] - eps);  // eqs. 7.1.3, 7.1.4
  Eigen::SparseMatrix<double> M(n, n);
  M.setFromTriplets(t.begin(), t.end());
  return M;
}

}  // namespace meshmark
