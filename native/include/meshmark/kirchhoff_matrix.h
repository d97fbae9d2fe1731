// meshmark: the Kirchhoff (combinatorial graph Laplacian) matrix of thesis ch. 7.
#pragma once
#include "meshmark/mesh.h"
#include <Eigen/SparseCore>

namespace meshmark {

// M(i,i) = |N(v_i)| - eps, M(i,j) = -1 for each edge (i,j)           (eqs. 7.1.3, 7.1.4)
// E: unique edges (unique_edges). eps = 0 gives the pure Kirchhoff matrix, whose rows sum to zero.
// Note the sign: eq. 7.1.4 subtracts eps, which leaves one eigenvalue -eps per connected component
// (the constant vectors); see docs/laplacian.md for why meshmark solves with +eps instead.
Eigen::SparseMatrix<double> kirchhoff_matrix(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E, double eps);

}  // namespace meshmark
