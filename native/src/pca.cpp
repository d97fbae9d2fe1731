#include "meshmark/pca.h"
#include "meshmark/error.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace meshmark {

PCAFrame pca_frame(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  const Eigen::Index rows = V.rows();
  const bool all = mask.size() == 0;
  if (!all && mask.size() != rows) throw MeshError("mask and V differ in length");
  auto row = [&](Eigen::Index i) { return V.data() + i * V.outerStride(); };
  Eigen::Index first = 0;
  while (first < rows && !all && !mask[first]) ++first;
  if (first == rows) throw MeshError("PCA of an empty point set");
  // Centroid and covariance in one pass, from moments about the first point (shifted data: no
  // cancellation from the distance of the point set to the coordinate origin).
  const Eigen::Vector3d o = Eigen::Map<const Eigen::Vector3d>(row(first));
  double s0 = 0, s1 = 0, s2 = 0, c00 = 0, c01 = 0, c02 = 0, c11 = 0, c12 = 0, c22 = 0, r2 = 0;
  Eigen::Index n = 0;
  for (Eigen::Index i = first; i < rows; ++i) {
    if (!all && !mask[i]) continue;
    const double* v = row(i);
    const double dx = v[0] - o[0], dy = v[1] - o[1], dz = v[2] - o[2];
    s0 += dx;
    s1 += dy;
    s2 += dz;
    c00 += dx * dx;
    c01 += dx * dy;
    c02 += dx * dz;
    c11 += dy * dy;
    c12 += dy * dz;
    c22 += dz * dz;
    r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
    ++n;
  }
  PCAFrame f;
  f.n = n;
  PCA& out = f.pca;
  const double inv = 1.0 / static_cast<double>(n);
  const Eigen::Vector3d mu(s0 * inv, s1 * inv, s2 * inv);  // centroid - o
  out.centroid = o + mu;
  f.radius = (std::sqrt(r2) + mu.norm()) * (1 + 1e-12);  // ||v - c|| <= ||v - o|| + ||o - c||
  Eigen::Matrix3d C;
  C << c00 * inv - mu[0] * mu[0], c01 * inv - mu[0] * mu[1], c02 * inv - mu[0] * mu[2],  //
      0, c11 * inv - mu[1] * mu[1], c12 * inv - mu[1] * mu[2],                            //
      0, 0, c22 * inv - mu[2] * mu[2];
  C(1, 0) = C(0, 1);
  C(2, 0) = C(0, 2);
  C(2, 1) = C(1, 2);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  for (int k = 0; k < 3; ++k) {  // the solver sorts ascending; we want descending
    out.eigenvalues[k] = std::max(0.0, es.eigenvalues()[2 - k]);
    out.axes.col(k) = es.eigenvectors().col(2 - k).normalized();
  }
  out.skewness.setZero();
  return f;
}

int pca_axis_sign(double m3, double pmin, double pmax, double lambda, const Eigen::Vector3d& q) {
  if (std::abs(m3) > 1e-9 * std::pow(lambda, 1.5)) return m3 > 0 ? 1 : -1;
  if (std::abs(pmax + pmin) > 1e-9 * std::sqrt(lambda)) return pmax >= -pmin ? 1 : -1;
  Eigen::Index j;
  q.cwiseAbs().maxCoeff(&j);
  return q[j] >= 0 ? 1 : -1;
}

PCA pca(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  PCAFrame f = pca_frame(V, mask);
  PCA& out = f.pca;
  const bool all = mask.size() == 0;
  // Sign rule: positive third central moment of the projections (see pca.h, docs/mesh_model.md).
  // One pass over the points for all three axes.
  Eigen::Vector3d m3 = Eigen::Vector3d::Zero(), pmax = Eigen::Vector3d::Zero(), pmin = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d Qt = out.axes.transpose();
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!all && !mask[i]) continue;
    const Eigen::Vector3d p = Qt * (V.row(i).transpose() - out.centroid);
    m3 += p.cwiseProduct(p).cwiseProduct(p);
    pmax = pmax.cwiseMax(p);
    pmin = pmin.cwiseMin(p);
  }
  m3 /= static_cast<double>(f.n);
  for (int k = 0; k < 3; ++k) {
    const int sign = pca_axis_sign(m3[k], pmin[k], pmax[k], out.eigenvalues[k], out.axes.col(k));
    out.axes.col(k) *= sign;
    out.skewness[k] = sign * m3[k];
  }
  return out;
}

PCA pca(const Eigen::Ref<const MatrixX3dR>& V) { return pca(V, VectorXb()); }

}  // namespace meshmark
