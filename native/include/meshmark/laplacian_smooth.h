// meshmark: uniform-weight Laplacian smoothing (the smoothing attack of thesis 6.3.2).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/vertex_adjacency.h"

namespace meshmark {

// `iterations` simultaneous (Jacobi) steps of
//   v_i <- v_i + lambda (1/|N(i)| sum_{j in N(i)} v_j - v_i)
// over the edge graph A (polygons as stored). Vertices without neighbours do not move; with
// fixed_boundary, vertices in `fixed` (sorted indices) do not move either. lambda = 0 is the
// identity. MeshError if lambda is not finite or iterations < 0.
MatrixX3dR laplacian_smooth(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, double lambda,
                            int iterations, const VectorXi& fixed = VectorXi());

}  // namespace meshmark
