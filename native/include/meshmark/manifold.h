// meshmark: manifoldness tests.
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/unique_edges.h"

namespace meshmark {

struct ManifoldReport {
  Offset non_manifold_edges = 0;     // edges on more than two face sides
  Offset non_manifold_vertices = 0;  // referenced vertices whose faces do not form one fan (disk or half-disk)
  bool edge_manifold() const { return non_manifold_edges == 0; }
  bool vertex_manifold() const { return non_manifold_vertices == 0; }
  bool manifold() const { return edge_manifold() && vertex_manifold(); }
};

// A vertex is manifold when the link formed by its faces (for each face, the two corners next
// to the vertex) is a single path or cycle. Both tests are on the polygons as stored.
ManifoldReport manifold_report(Index n_vertices, const Polygons& P, const EdgeList& edges);

}  // namespace meshmark
