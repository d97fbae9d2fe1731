// meshmark: connected components of the edge graph.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct Components {
  VectorXi label;  // (n,) component of each vertex, numbered 0.. in order of the lowest vertex index;
                   // -1 for vertices that no edge touches (unreferenced vertices)
  Index count = 0; // number of components (unreferenced vertices are not counted)
};

// Union-find over the edges E.
Components connected_components(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E);

}  // namespace meshmark
