#include "meshmark/unit_cube_normalize.h"
#include "meshmark/error.h"
#include "meshmark/pca.h"

#include <limits>

namespace meshmark {

MatrixX3dR unit_cube_normalize(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  const PCA p = pca(V, mask);
  const Eigen::Index n = V.rows();
  MatrixX3dR X(n, 3);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::RowVector3d x = (V.row(i) - p.centroid.transpose()) * p.axes;  // PCA frame (§8.1.1)
    X.row(i) = x;
    if (mask.size() == 0 || mask[i]) {
      lo = lo.cwiseMin(x.transpose());
      hi = hi.cwiseMax(x.transpose());
    }
  }
  const double side = (hi - lo).maxCoeff();
  if (!(side > 0)) throw MeshError("all vertices coincide: the mesh cannot be scaled into the unit cube");
  const Eigen::RowVector3d mid = 0.5 * (lo + hi).transpose();
  for (Eigen::Index i = 0; i < n; ++i) X.row(i) = (X.row(i) - mid) / side + Eigen::RowVector3d::Constant(0.5);
  return X;
}

}  // namespace meshmark
