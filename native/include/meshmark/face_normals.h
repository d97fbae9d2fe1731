// meshmark: per-face unit normals of a triangle mesh.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (t,3) unit normals (right-hand rule on the winding). A zero-area triangle gets (0,0,0).
MatrixX3dR face_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
