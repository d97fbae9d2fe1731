// meshmark: the two faces of every interior edge of a triangle mesh, without a search tree.
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"

namespace meshmark {

struct EdgeFaces {
  VectorXi f0, f1;  // (e,) the first and second face (in face order) on each edge of `edges`; -1 if none
};

// `edges` from unique_edges of T, `A` = vertex_adjacency of edges.E. The index of edge (a, b), a < b,
// is found from A (sorted neighbours) in O(valence): no binary search over all edges.
EdgeFaces edge_faces(const EdgeList& edges, const Adjacency& A, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
