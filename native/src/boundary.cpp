#include "meshmark/boundary.h"

#include <vector>

namespace meshmark {

VectorXi boundary_edges(const EdgeList& edges) {
  std::vector<Index> out;
  for (Eigen::Index e = 0; e < edges.face_count.size(); ++e)
    if (edges.face_count[e] == 1) out.push_back(static_cast<Index>(e));
  return Eigen::Map<VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

VectorXi boundary_vertices(Index n_vertices, const EdgeList& edges) {
  std::vector<std::uint8_t> mark(static_cast<size_t>(n_vertices), 0);
  for (Eigen::Index e = 0; e < edges.face_count.size(); ++e)
    if (edges.face_count[e] == 1) mark[edges.E(e, 0)] = mark[edges.E(e, 1)] = 1;
  std::vector<Index> out;
  for (Index v = 0; v < n_vertices; ++v)
    if (mark[v]) out.push_back(v);
  return Eigen::Map<VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

}  // namespace meshmark
