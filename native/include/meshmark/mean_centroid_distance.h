// meshmark: d-bar of eq. 6.3.12, the mean distance from the vertices to their centroid.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (1/n) sum_i |v_i - c|, c = (1/n) sum_i v_i, over all rows of V (callers pass referenced vertices).
double mean_centroid_distance(const Eigen::Ref<const MatrixX3dR>& V);

}  // namespace meshmark
