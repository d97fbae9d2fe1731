#include "meshmark/mean_edge_length.h"

namespace meshmark {

double mean_edge_length(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX2iR>& E) {
  double total = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) total += (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return E.rows() ? total / static_cast<double>(E.rows()) : 0.0;
}

}  // namespace meshmark
