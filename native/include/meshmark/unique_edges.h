// meshmark: the edge graph of a polygon mesh.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct EdgeList {
  MatrixX2iR E;        // (e,2) unique undirected edges with E(i,0) < E(i,1), sorted lexicographically
  VectorXi face_count; // (e,) number of face sides lying on each edge (1 = boundary, >2 = non-manifold)
};

// Unique edges of the polygon mesh as stored: a quad contributes its 4 sides, never a diagonal.
// O(c) bucket sort by the smaller endpoint.
EdgeList unique_edges(Index n_vertices, const Polygons& P);

}  // namespace meshmark
