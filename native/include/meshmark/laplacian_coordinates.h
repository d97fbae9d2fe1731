// meshmark: Laplacian coordinates and their lengths (thesis ch. 7).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/vertex_adjacency.h"

namespace meshmark {

// L = (K - eps I) X, row i: |N(v_i)| x_i - sum_{j in N(i)} x_j - eps x_i      (eqs. 7.1.2-7.1.4)
// computed directly from the CSR adjacency (no matrix is formed). eps = 0 (meshmark's default for
// measuring) makes L invariant under translation.
MatrixX3dR laplacian_coordinates(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, double eps = 0.0);

// d_i = ||L_i||                                                                 (eq. 7.1.5)
Eigen::VectorXd laplacian_lengths(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, double eps = 0.0);

// The same lengths straight from the unique edges (e,2), one pass over the edges and no adjacency:
// the extraction's path. Also returns the mean edge length (the scale unit of docs/laplacian.md) if
// `mean_edge_length` is given.
Eigen::VectorXd laplacian_lengths(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX2iR>& E,
                                  double eps = 0.0, double* mean_edge_length = nullptr);

}  // namespace meshmark
