#include "meshmark/manifold.h"

#include <algorithm>
#include <vector>

namespace meshmark {

ManifoldReport manifold_report(Index n_vertices, const Polygons& P, const EdgeList& edges) {
  ManifoldReport R;
  for (Eigen::Index e = 0; e < edges.face_count.size(); ++e)
    if (edges.face_count[e] > 2) ++R.non_manifold_edges;

  // Link of each vertex: for every corner at v, the segment (previous corner, next corner).
  std::vector<Offset> start(static_cast<size_t>(n_vertices) + 1, 0);
  const Offset m = P.n_faces();
  for (Offset c = 0; c < P.n_corners(); ++c) ++start[P.indices[c] + 1];
  for (Index i = 0; i < n_vertices; ++i) start[i + 1] += start[i];
  std::vector<std::pair<Index, Index>> link(static_cast<size_t>(start[n_vertices]));
  std::vector<Offset> fill(start.begin(), start.end() - 1);
  for (Offset f = 0; f < m; ++f) {
    const Offset b = P.offsets[f], e = P.offsets[f + 1], k = e - b;
    for (Offset j = 0; j < k; ++j) {
      const Index v = P.indices[b + j];
      link[fill[v]++] = {P.indices[b + (j + k - 1) % k], P.indices[b + (j + 1) % k]};
    }
  }
  std::vector<Index> nodes, deg, parent;
  for (Index v = 0; v < n_vertices; ++v) {
    const Offset b = start[v], e = start[v + 1];
    if (b == e) continue;
    nodes.clear();
    for (Offset i = b; i < e; ++i) {
      nodes.push_back(link[i].first);
      nodes.push_back(link[i].second);
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    const size_t k = nodes.size();
    deg.assign(k, 0);
    parent.resize(k);
    for (size_t i = 0; i < k; ++i) parent[i] = static_cast<Index>(i);
    auto id = [&](Index x) { return static_cast<Index>(std::lower_bound(nodes.begin(), nodes.end(), x) - nodes.begin()); };
    auto root = [&](Index x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    bool ok = true;
    size_t n_sets = k;
    for (Offset i = b; i < e; ++i) {
      const Index a = id(link[i].first), c = id(link[i].second);
      if (++deg[a] > 2 || ++deg[c] > 2) ok = false;
      const Index ra = root(a), rc = root(c);
      if (ra != rc) {
        parent[ra] = rc;
        --n_sets;
      }
    }
    if (!ok || n_sets != 1) ++R.non_manifold_vertices;
  }
  return R;
}

}  // namespace meshmark
