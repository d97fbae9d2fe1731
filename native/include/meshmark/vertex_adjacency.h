// meshmark: vertex adjacency of the edge graph in compressed sparse row (CSR) form.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct Adjacency {
  VectorXo ptr;  // (n+1,) neighbours of vertex i are nbr[ptr[i] .. ptr[i+1])
  VectorXi nbr;  // (2e,) sorted ascending within each vertex
};

// CSR adjacency from unique edges E (as returned by unique_edges).
Adjacency vertex_adjacency(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E);

// Valence (number of distinct neighbours) of each vertex; 0 for unreferenced vertices.
VectorXi valence(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E);

}  // namespace meshmark
