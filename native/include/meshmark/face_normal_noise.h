// meshmark: how far a face's unit normal can turn when its vertices move (the noise bounds of the
// stabilised steganalysis sets, feature_statistics.h).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (t,) first-order bound of the angle (radians) the unit normal of each triangle turns when every vertex
// coordinate moves by at most s_v (s = vertex_noise, one entry per vertex; empty = 1 for all):
// |d(e1 x e2)| / |e1 x e2| <= 2 sqrt(3) max_v s_v (|e1| + |e2|) / |e1 x e2|, e1 = b - a, e2 = c - a,
// taken with the perimeter in place of |e1| + |e2| so that it does not depend on which corner comes first.
// +inf for a zero-area triangle.
Eigen::VectorXd face_normal_noise(const Eigen::Ref<const MatrixX3dR>& X, const Eigen::Ref<const MatrixX3iR>& T,
                                  const Eigen::Ref<const Eigen::VectorXd>& vertex_noise = Eigen::VectorXd());

}  // namespace meshmark
