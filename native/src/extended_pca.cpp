#include "meshmark/extended_pca.h"
#include "meshmark/error.h"
#include "meshmark/pca.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace meshmark {

// §8.1.1 in extended precision (docs/steganalysis.md §2, "Invariance"): the centroid, the covariance,
// its eigenvectors and the third moments of the sign rule are accumulated in long double (64-bit
// mantissa on x86-64). Sums of n terms then carry ~n * 1e-19 relative error, so the frame does not
// depend on the vertex order, and its own error drops below the rounding of the input coordinates.
ExtendedPca extended_pca(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  using LD = long double;
  using V3 = Eigen::Matrix<LD, 3, 1>;
  using M3 = Eigen::Matrix<LD, 3, 3>;
  const Eigen::Index n = V.rows();
  const bool all = mask.size() == 0;
  if (!all && mask.size() != n) throw MeshError("mask and V differ in length");
  auto sel = [&](Eigen::Index i) { return all || mask[i]; };
  auto row = [&](Eigen::Index i) { return V3(V(i, 0), V(i, 1), V(i, 2)); };
  V3 c = V3::Zero();
  Eigen::Index m = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (sel(i)) c += row(i), ++m;
  if (m == 0) throw MeshError("PCA of an empty point set");
  c /= static_cast<LD>(m);
  M3 C = M3::Zero();
  for (Eigen::Index i = 0; i < n; ++i)
    if (sel(i)) {
      const V3 d = row(i) - c;
      C.noalias() += d * d.transpose();
    }
  C /= static_cast<LD>(m);
  Eigen::SelfAdjointEigenSolver<M3> es(C);
  M3 Q;
  V3 lambda;
  for (int k = 0; k < 3; ++k) {  // the solver sorts ascending; the axes go descending
    Q.col(k) = es.eigenvectors().col(2 - k).normalized();
    lambda[k] = std::max<LD>(0, es.eigenvalues()[2 - k]);
  }
  // Sign rule of pca.h (positive third central moment of the projections, then the farther extreme,
  // then the largest component), on the extended-precision projections.
  V3 m3 = V3::Zero(), pmin = V3::Zero(), pmax = V3::Zero();
  for (Eigen::Index i = 0; i < n; ++i)
    if (sel(i)) {
      const V3 p = Q.transpose() * (row(i) - c);
      m3 += p.cwiseProduct(p).cwiseProduct(p);
      pmin = pmin.cwiseMin(p), pmax = pmax.cwiseMax(p);
    }
  m3 /= static_cast<LD>(m);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d q = Q.col(k).cast<double>();
    Q.col(k) *= static_cast<LD>(pca_axis_sign(static_cast<double>(m3[k]), static_cast<double>(pmin[k]),
                                              static_cast<double>(pmax[k]), static_cast<double>(lambda[k]), q));
  }
  return {c, Q, lambda};
}

}  // namespace meshmark
