// meshmark: the input check shared by the steganalysis feature sets.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (n,) 1 for the vertices used by a triangle. MeshError for an index out of range, no triangle, or
// fewer than 4 referenced vertices ("mesh too small for steganalysis features").
VectorXb feature_mesh_check(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
