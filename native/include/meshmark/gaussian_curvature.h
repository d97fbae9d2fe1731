// meshmark: discrete Gaussian curvature as the angle deficit (thesis eq. 5.1.1, eq. 4.3.23).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct GaussianCurvature {
  Eigen::VectorXd kappa;  // (n,) radians
  VectorXb interior;      // (n,) 1: referenced, and no incident edge is a boundary or non-manifold edge
  VectorXb boundary;      // (n,) 1: on an edge with exactly one triangle side
};

// kappa_v = 2 pi - sum_i alpha_i over the triangle corners at v                            (eq. 5.1.1)
// for interior vertices. A boundary vertex has a half disc, not a disc, as its flat reference, so it
// gets the boundary angle deficit kappa_v = pi - sum_i alpha_i (0 on a straight flat boundary; the
// discrete geodesic curvature of the boundary). A vertex on a non-manifold edge (> 2 triangle sides)
// keeps 2 pi - sum alpha but is not interior. Unreferenced vertices: kappa = 0, interior = 0.
// The triangles are used as given (angle_sum / interior_angles: atan2, zero-length side -> 0).
GaussianCurvature gaussian_curvature(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
