#include "meshmark/unit_cube_normalize.h"
#include "meshmark/error.h"
#include "meshmark/extended_pca.h"

#include <cmath>
#include <limits>

namespace meshmark {

// §8.1.1 in extended precision (docs/steganalysis.md §2, "Invariance"): the centroid, the covariance,
// its eigenvectors, the third moments of the sign rule and the projection are all accumulated in long
// double (64-bit mantissa on x86-64), and rounded to double once, at the end. Sums of n terms then
// carry ~n * 1e-19 relative error, so the double results do not depend on the vertex order (bit-equal
// after a permutation in practice), and the frame's own error (pca.h in double: up to 1e-14 of the
// unit cube) drops below the rounding of the input coordinates.
MatrixX3dR unit_cube_normalize(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  using LD = long double;
  using V3 = Eigen::Matrix<LD, 3, 1>;
  const Eigen::Index n = V.rows();
  const bool all = mask.size() == 0;
  auto sel = [&](Eigen::Index i) { return all || mask[i]; };
  auto row = [&](Eigen::Index i) { return V3(V(i, 0), V(i, 1), V(i, 2)); };
  const ExtendedPca pca = extended_pca(V, mask);  // checks the mask
  const V3& c = pca.centroid;
  const auto& Q = pca.axes;
  Eigen::Matrix<LD, Eigen::Dynamic, 3> P(n, 3);
  V3 lo = V3::Constant(std::numeric_limits<LD>::infinity()), hi = -lo;
  for (Eigen::Index i = 0; i < n; ++i) {
    const V3 p = Q.transpose() * (row(i) - c);  // PCA frame (§8.1.1)
    P.row(i) = p.transpose();
    if (sel(i)) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  const LD side = (hi - lo).maxCoeff();
  if (!(side > 0)) throw MeshError("all vertices coincide: the mesh cannot be scaled into the unit cube");
  const V3 mid = (lo + hi) / 2;
  MatrixX3dR X(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) X(i, k) = static_cast<double>((P(i, k) - mid[k]) / side + 0.5L);
  return X;
}

}  // namespace meshmark
