#include "meshmark/radial_distances.h"
#include "meshmark/error.h"

namespace meshmark {

Eigen::Vector3d masked_centroid(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Index n = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (mask[i]) {
      s += V.row(i).transpose();
      ++n;
    }
  if (n == 0) throw MeshError("the mesh has no (referenced) vertices");
  return s / static_cast<double>(n);
}

Eigen::VectorXd radial_distances(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                 const Eigen::Vector3d& c) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (mask[i]) rho[i] = (V.row(i).transpose() - c).norm();  // eq. 6.1.1
  return rho;
}

MatrixX3dR radial_rescale(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Vector3d& c,
                          const Eigen::Ref<const Eigen::VectorXd>& rho, const Eigen::Ref<const Eigen::VectorXd>& rho_new) {
  MatrixX3dR out = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (rho_new[i] != rho[i] && rho[i] > 0) {
      const double s = rho_new[i] / rho[i];
      for (int j = 0; j < 3; ++j) out(i, j) = c[j] + (V(i, j) - c[j]) * s;
    }
  return out;
}

}  // namespace meshmark
