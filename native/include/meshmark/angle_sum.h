// meshmark: sum of interior angles around each vertex.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (n,) sum of the interior angles incident to each vertex, radians (0 for unreferenced vertices).
// For an interior vertex, 2*pi - angle_sum is the angle deficit (discrete Gaussian curvature, ch. 5).
Eigen::VectorXd angle_sum(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
