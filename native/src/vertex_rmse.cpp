#include "meshmark/vertex_rmse.h"
#include "meshmark/error.h"

#include <cmath>

namespace meshmark {

double vertex_rmse(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3dR>& V2) {
  if (V.rows() != V2.rows())
    throw MeshError("vertex RMSE needs corresponding vertices: " + std::to_string(V.rows()) + " and " +
                    std::to_string(V2.rows()) + " vertices");
  if (V.rows() == 0) throw MeshError("mesh has no vertices");
  double s = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) s += (V.row(i) - V2.row(i)).squaredNorm();
  return std::sqrt(s / static_cast<double>(V.rows()));
}

}  // namespace meshmark
