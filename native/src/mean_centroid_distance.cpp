#include "meshmark/mean_centroid_distance.h"

namespace meshmark {

double mean_centroid_distance(const Eigen::Ref<const MatrixX3dR>& V) {  // d-bar of eq. 6.3.12
  const Eigen::Index n = V.rows();
  if (n == 0) return 0.0;
  const Eigen::RowVector3d c = V.colwise().sum() / static_cast<double>(n);
  double s = 0;
  for (Eigen::Index i = 0; i < n; ++i) s += (V.row(i) - c).norm();
  return s / static_cast<double>(n);
}

}  // namespace meshmark
