// meshmark: interior angles of a triangle mesh.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// (t,3) angle in radians at each corner: A(f,k) is the angle at T(f,k). Computed as
// atan2(|a x b|, a . b), which is accurate for needle triangles; a corner with a zero-length
// side gets 0.
Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> interior_angles(
    const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
