#include "meshmark/pca.h"
#include "meshmark/error.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace meshmark {

PCA pca(const Eigen::Ref<const MatrixX3dR>& V) {
  const Eigen::Index n = V.rows();
  if (n == 0) throw MeshError("PCA of an empty point set");
  PCA out;
  out.centroid = V.colwise().mean().transpose();
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d d = V.row(i).transpose() - out.centroid;
    C.noalias() += d * d.transpose();
  }
  C /= static_cast<double>(n);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  for (int k = 0; k < 3; ++k) {  // the solver sorts ascending; we want descending
    out.eigenvalues[k] = std::max(0.0, es.eigenvalues()[2 - k]);
    out.axes.col(k) = es.eigenvectors().col(2 - k).normalized();
  }
  // Sign rule: positive third central moment of the projections (see pca.h, docs/mesh_model.md).
  // One pass over the points for all three axes.
  Eigen::Vector3d m3 = Eigen::Vector3d::Zero(), pmax = Eigen::Vector3d::Zero(), pmin = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d Qt = out.axes.transpose();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = Qt * (V.row(i).transpose() - out.centroid);
    m3 += p.cwiseProduct(p).cwiseProduct(p);
    pmax = pmax.cwiseMax(p);
    pmin = pmin.cwiseMin(p);
  }
  m3 /= static_cast<double>(n);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d q = out.axes.col(k);
    const double scale = std::pow(out.eigenvalues[k], 1.5);
    int sign;
    if (std::abs(m3[k]) > 1e-9 * scale) sign = m3[k] > 0 ? 1 : -1;
    else if (std::abs(pmax[k] + pmin[k]) > 1e-9 * std::sqrt(out.eigenvalues[k]))
      sign = pmax[k] >= -pmin[k] ? 1 : -1;
    else {
      Eigen::Index j;
      q.cwiseAbs().maxCoeff(&j);
      sign = q[j] >= 0 ? 1 : -1;
    }
    out.axes.col(k) = sign * q;
    out.skewness[k] = sign * m3[k];
  }
  return out;
}

}  // namespace meshmark
