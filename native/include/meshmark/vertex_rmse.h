// meshmark: root-mean-square error between corresponding vertices.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// sqrt((1/n) sum_i |v_i - v'_i|^2). MeshError if the shapes differ or V is empty.
double vertex_rmse(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3dR>& V2);

}  // namespace meshmark
