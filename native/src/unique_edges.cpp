#include "meshmark/unique_edges.h"

#include <algorithm>
#include <vector>

namespace meshmark {

EdgeList unique_edges(Index n_vertices, const Polygons& P) {
  const Offset m = P.n_faces();
  // Bucket every face side (a,b), a<b, by a; then sort and merge each bucket (buckets are tiny).
  std::vector<Offset> start(static_cast<size_t>(n_vertices) + 1, 0);
  for (Offset f = 0; f < m; ++f) {
    const Offset b = P.offsets[f], e = P.offsets[f + 1];
    for (Offset c = b; c < e; ++c) {
      const Index u = P.indices[c], v = P.indices[c + 1 < e ? c + 1 : b];
      ++start[std::min(u, v) + 1];
    }
  }
  for (Index i = 0; i < n_vertices; ++i) start[i + 1] += start[i];
  std::vector<Index> other(static_cast<size_t>(start[n_vertices]));
  std::vector<Offset> fill(start.begin(), start.end() - 1);
  for (Offset f = 0; f < m; ++f) {
    const Offset b = P.offsets[f], e = P.offsets[f + 1];
    for (Offset c = b; c < e; ++c) {
      const Index u = P.indices[c], v = P.indices[c + 1 < e ? c + 1 : b];
      other[fill[std::min(u, v)]++] = std::max(u, v);
    }
  }
  std::vector<Index> ea, eb, cnt;
  ea.reserve(other.size() / 2 + 1);
  eb.reserve(other.size() / 2 + 1);
  cnt.reserve(other.size() / 2 + 1);
  for (Index a = 0; a < n_vertices; ++a) {
    auto first = other.begin() + start[a], last = other.begin() + start[a + 1];
    std::sort(first, last);
    for (auto it = first; it != last;) {
      auto jt = it;
      while (jt != last && *jt == *it) ++jt;
      ea.push_back(a);
      eb.push_back(*it);
      cnt.push_back(static_cast<Index>(jt - it));
      it = jt;
    }
  }
  EdgeList out;
  out.E.resize(static_cast<Eigen::Index>(ea.size()), 2);
  out.face_count.resize(static_cast<Eigen::Index>(ea.size()));
  for (size_t i = 0; i < ea.size(); ++i) {
    out.E(i, 0) = ea[i];
    out.E(i, 1) = eb[i];
    out.face_count[i] = cnt[i];
  }
  return out;
}

}  // namespace meshmark
