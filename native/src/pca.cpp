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
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d q = out.axes.col(k);
    double m3 = 0, pmax = 0, pmin = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double p = (V.row(i).transpose() - out.centroid).dot(q);
      m3 += p * p * p;
      pmax = std::max(pmax, p);
      pmin = std::min(pmin, p);
    }
    m3 /= static_cast<double>(n);
    const double scale = std::pow(out.eigenvalues[k], 1.5);
    int sign;
    if (std::abs(m3) > 1e-9 * scale) sign = m3 > 0 ? 1 : -1;
    else if (std::abs(pmax + pmin) > 1e-9 * std::sqrt(out.eigenvalues[k]))
      sign = pmax >= -pmin ? 1 : -1;
    else {
      Eigen::Index j;
      q.cwiseAbs().maxCoeff(&j);
      sign = q[j] >= 0 ? 1 : -1;
    }
    out.axes.col(k) = sign * q;
    out.skewness[k] = sign * m3;
  }
  return out;
}

}  // namespace meshmark
