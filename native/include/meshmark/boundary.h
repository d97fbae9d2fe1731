// meshmark: boundary of a polygon mesh.
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/unique_edges.h"

namespace meshmark {

// Indices (into edges.E) of the boundary edges: edges lying on exactly one face side.
VectorXi boundary_edges(const EdgeList& edges);

// Sorted indices of the vertices that touch a boundary edge.
VectorXi boundary_vertices(Index n_vertices, const EdgeList& edges);

}  // namespace meshmark
