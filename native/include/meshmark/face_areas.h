// meshmark: per-face areas of a triangle mesh.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (t,) triangle areas, in squared model units.
Eigen::VectorXd face_areas(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
