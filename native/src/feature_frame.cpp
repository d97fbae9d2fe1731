#include "meshmark/feature_frame.h"
#include "meshmark/error.h"
#include "meshmark/pca.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace meshmark {

// As unit_cube_normalize.cpp: centroid, covariance, eigenvectors, sign rule and projection in long double,
// rounded to double once (docs/steganalysis.md §2, "Invariance").
FeatureFrame feature_frame(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
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
  for (int k = 0; k < 3; ++k) {
    Q.col(k) = es.eigenvectors().col(2 - k).normalized();
    lambda[k] = std::max<LD>(0, es.eigenvalues()[2 - k]);
  }
  FeatureFrame fr;
  fr.group = {0, 1, 2};
  for (int k = 0; k < 2; ++k)
    if (lambda[k] - lambda[k + 1] <= static_cast<LD>(kFrameDegenerateGap) * lambda[0]) fr.group[k + 1] = fr.group[k];
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
  Eigen::Matrix<LD, Eigen::Dynamic, 3> P(n, 3);
  V3 lo = V3::Constant(std::numeric_limits<LD>::infinity()), hi = -lo, rmax = V3::Zero();  // rmax: per group
  for (Eigen::Index i = 0; i < n; ++i) {
    const V3 p = Q.transpose() * (row(i) - c);
    P.row(i) = p.transpose();
    if (!sel(i)) continue;
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    V3 g2 = V3::Zero();
    for (int k = 0; k < 3; ++k) g2[fr.group[k]] += p[k] * p[k];
    for (int k = 0; k < 3; ++k) rmax[k] = std::max(rmax[k], std::sqrt(g2[k]));
  }
  LD side = 0;
  V3 mid = V3::Zero();
  for (int k = 0; k < 3; ++k) {
    const bool single = fr.group[k] == k && (k == 2 || fr.group[k + 1] != k);
    if (single) {
      side = std::max(side, hi[k] - lo[k]);
      mid[k] = (lo[k] + hi[k]) / 2;
    } else if (fr.group[k] == k) {
      side = std::max(side, 2 * rmax[k]);  // the group's enclosing-ball diameter about the centroid
    }
  }
  if (!(side > 0)) throw MeshError("all vertices coincide: the mesh cannot be scaled into the unit cube");
  fr.X.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) fr.X(i, k) = static_cast<double>((P(i, k) - mid[k]) / side + 0.5L);
  for (int k = 0; k < 3; ++k) {
    fr.centroid[k] = static_cast<double>(-mid[k] / side + 0.5L);
    fr.lambda[k] = static_cast<double>(lambda[k] / (side * side));
  }
  return fr;
}

Eigen::RowVector3d pooled_abs(const FeatureFrame& fr, const Eigen::Ref<const Eigen::RowVector3d>& d) {
  Eigen::RowVector3d s2 = Eigen::RowVector3d::Zero(), cnt = Eigen::RowVector3d::Zero(), out;
  for (int k = 0; k < 3; ++k) s2[fr.group[k]] += d[k] * d[k], cnt[fr.group[k]] += 1;
  for (int k = 0; k < 3; ++k)
    out[k] = cnt[fr.group[k]] == 1 ? std::abs(d[k]) : std::sqrt(s2[fr.group[k]] / cnt[fr.group[k]]);
  return out;
}

}  // namespace meshmark
