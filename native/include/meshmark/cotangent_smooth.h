// meshmark: cotangent-weight Laplacian smoothing (variant of the smoothing attack).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// `iterations` explicit Jacobi steps of v_i <- v_i + lambda (sum_j w_ij v_j / sum_j w_ij - v_i), with
// w_ij = max(0, (cot a_ij + cot b_ij) / 2) recomputed from the current positions at each step
// (a_ij, b_ij: angles opposite edge ij in its triangles; degenerate corners contribute 0). Where
// sum_j w_ij = 0 the uniform weights are used. Vertices in `fixed` (sorted) and isolated vertices
// do not move. MeshError if lambda is not finite or iterations < 0.
MatrixX3dR cotangent_smooth(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                            double lambda, int iterations, const VectorXi& fixed = VectorXi());

}  // namespace meshmark
