#include "meshmark/pca.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace meshmark {

namespace {

// The PCA of the rows i with selected(i), in row order: centroid, covariance, then the sign pass.
template <class Selected>
PCA pca_rows(const Eigen::Ref<const MatrixX3dR>& V, Selected selected, std::vector<double>* proj) {
  const Eigen::Index rows = V.rows();
  auto row = [&](Eigen::Index i) { return V.data() + i * V.outerStride(); };
  // Centroid and covariance in one pass, from moments about the first point (shifted data: no
  // cancellation from the distance of the point set to the coordinate origin).
  Eigen::Index first = 0;
  while (first < rows && !selected(first)) ++first;
  if (first == rows) throw MeshError("PCA of an empty point set");
  const Eigen::Vector3d o = Eigen::Map<const Eigen::Vector3d>(row(first));
  double s0 = 0, s1 = 0, s2 = 0, c00 = 0, c01 = 0, c02 = 0, c11 = 0, c12 = 0, c22 = 0;
  Eigen::Index n = 0;
  for (Eigen::Index i = first; i < rows; ++i)
    if (selected(i)) {
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
      ++n;
    }
  PCA out;
  const double inv = 1.0 / static_cast<double>(n);
  const Eigen::Vector3d mu(s0 * inv, s1 * inv, s2 * inv);  // centroid - o
  out.centroid = o + mu;
  const Eigen::Vector3d& c = out.centroid;
  c00 = c00 * inv - mu[0] * mu[0];
  c01 = c01 * inv - mu[0] * mu[1];
  c02 = c02 * inv - mu[0] * mu[2];
  c11 = c11 * inv - mu[1] * mu[1];
  c12 = c12 * inv - mu[1] * mu[2];
  c22 = c22 * inv - mu[2] * mu[2];
  Eigen::Matrix3d C;
  C << c00, c01, c02, c01, c11, c12, c02, c12, c22;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  for (int k = 0; k < 3; ++k) {  // the solver sorts ascending; we want descending
    out.eigenvalues[k] = std::max(0.0, es.eigenvalues()[2 - k]);
    out.axes.col(k) = es.eigenvectors().col(2 - k).normalized();
  }
  // Sign rule: positive third central moment of the projections (see pca.h, docs/mesh_model.md).
  // One pass over the points for all three axes.
  Eigen::Vector3d m3 = Eigen::Vector3d::Zero(), pmax = Eigen::Vector3d::Zero(), pmin = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d Qt = out.axes.transpose();
  if (proj) {
    if (proj->capacity() < static_cast<size_t>(n)) {
      proj->clear();
      proj->reserve(n);
      advise_huge_pages(proj->data(), n * sizeof(double));
    }
    proj->resize(n);
  }
  for (Eigen::Index i = 0, j = 0; i < rows; ++i) {
    if (!selected(i)) continue;
    const Eigen::Vector3d p = Qt * (Eigen::Map<const Eigen::Vector3d>(row(i)) - c);
    m3 += p.cwiseProduct(p).cwiseProduct(p);
    pmax = pmax.cwiseMax(p);
    pmin = pmin.cwiseMin(p);
    if (proj) (*proj)[j++] = p[0];
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
    out.proj_min[k] = sign > 0 ? pmin[k] : -pmax[k];
    out.proj_max[k] = sign > 0 ? pmax[k] : -pmin[k];
    if (k == 0 && proj && sign < 0)
      for (double& p : *proj) p = -p;
  }
  return out;
}

}  // namespace

PCA pca(const Eigen::Ref<const MatrixX3dR>& V) {
  return pca_rows(V, [](Eigen::Index) { return true; }, nullptr);
}

PCA pca(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
        std::vector<double>* first_projections) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  return pca_rows(V, [&](Eigen::Index i) { return mask[i] != 0; }, first_projections);
}

}  // namespace meshmark
