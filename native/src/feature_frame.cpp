#include "meshmark/feature_frame.h"
#include "meshmark/error.h"
#include "meshmark/extended_pca.h"
#include "meshmark/pca.h"

#include <cmath>
#include <limits>

namespace meshmark {

// As unit_cube_normalize.cpp: centroid, covariance, eigenvectors, sign rule and projection in long double,
// rounded to double once (docs/steganalysis.md §2, "Invariance").
FeatureFrame feature_frame(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  using LD = long double;
  using V3 = Eigen::Matrix<LD, 3, 1>;
  const Eigen::Index n = V.rows();
  const bool all = mask.size() == 0;
  auto sel = [&](Eigen::Index i) { return all || mask[i]; };
  auto row = [&](Eigen::Index i) { return V3(V(i, 0), V(i, 1), V(i, 2)); };
  const ExtendedPca pca = extended_pca(V, mask);  // checks the mask
  const V3& c = pca.centroid;
  const auto& Q = pca.axes;
  const V3& lambda = pca.lambda;
  FeatureFrame fr;
  fr.group = {0, 1, 2};
  for (int k = 0; k < 2; ++k)
    if (lambda[k] - lambda[k + 1] <= static_cast<LD>(kFrameDegenerateGap) * lambda[0]) fr.group[k + 1] = fr.group[k];
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
