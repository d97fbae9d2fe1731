// meshmark: the vertex orderings pi_1 / pi_2 of thesis §4.3.2: the projection of quantized vertices on
// their first principal axis, computed so that it is bit-identical under any vertex permutation.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct StegoOrder {
  VectorXi order;      // (n,) vertex indices in ascending projection order
  VectorXb first;      // (n,) per position: 1 when the vertex starts a tie group (0: identical key to the previous)
  Eigen::Vector3d axis;  // the oriented first principal axis
  Eigen::Vector3d centroid;
};

// Q: (n,3) quantized vertices, t: (n,) cell exponents, (E, o) the stego frame (|x - o| <= 2^E).
// Permutation invariance: the centroid, the covariance and the third moment used by the sign rule are
// exact integer sums (__int128) of per-vertex fixed-point values (the coordinates on the grid 2^(E-40),
// the products and cubes on grids scaled to 2^60), so they do not depend on the summation order. The
// axis sign follows meshmark::pca_axis_sign (positive third moment of the projections; then the far
// side; then the largest component positive). Sort key: (projection, bit patterns of x, y, z, t,
// neighbourhood hash); the hash is the wrapping sum, over the faces P around the vertex and their other
// corners, of a 64-bit mix of the corner's (x, y, z, t): it separates distinct vertices that quantize
// into the same cell, and it does not depend on the vertex or face order. Vertices with equal keys are
// a tie group (indistinguishable to the extractor: they carry the same bits).
StegoOrder stego_order(const Eigen::Ref<const MatrixX3dR>& Q, const Eigen::Ref<const VectorXi>& t, int E,
                       const Eigen::Vector3d& o, const Polygons& P);

}  // namespace meshmark
