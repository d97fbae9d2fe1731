#include "meshmark/angle_sum.h"
#include "meshmark/interior_angles.h"

namespace meshmark {

Eigen::VectorXd angle_sum(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const auto A = interior_angles(V, T);
  Eigen::VectorXd S = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) S[T(f, k)] += A(f, k);
  return S;
}

}  // namespace meshmark
