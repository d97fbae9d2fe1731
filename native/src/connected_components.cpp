#include "meshmark/connected_components.h"

#include <numeric>
#include <vector>

namespace meshmark {

namespace {
Index find_root(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];  // path halving
    x = parent[x];
  }
  return x;
}
}  // namespace

Components connected_components(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E) {
  std::vector<Index> parent(static_cast<size_t>(n_vertices));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<std::uint8_t> touched(static_cast<size_t>(n_vertices), 0);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Index a = find_root(parent, E(e, 0)), b = find_root(parent, E(e, 1));
    touched[E(e, 0)] = touched[E(e, 1)] = 1;
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // root = lowest index
  }
  Components C;
  C.label = VectorXi::Constant(n_vertices, -1);
  std::vector<Index> root_label(static_cast<size_t>(n_vertices), -1);
  for (Index v = 0; v < n_vertices; ++v) {
    if (!touched[v]) continue;
    const Index r = find_root(parent, v);
    if (root_label[r] < 0) root_label[r] = C.count++;
    C.label[v] = root_label[r];
  }
  return C;
}

}  // namespace meshmark
