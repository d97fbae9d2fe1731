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
  // Sort each bucket (a handful of entries: insertion sort), then write the distinct pairs with their
  // multiplicities straight into the output, sized for the worst case and trimmed at the end.
  EdgeList out;
  const Offset total = start[n_vertices];
  out.E.resize(static_cast<Eigen::Index>(total), 2);
  out.face_count.resize(static_cast<Eigen::Index>(total));
  Eigen::Index ne = 0;
  for (Index a = 0; a < n_vertices; ++a) {
    Index* first = other.data() + start[a];
    Index* last = other.data() + start[a + 1];
    for (Index* it = first + 1; it < last; ++it) {
      const Index x = *it;
      Index* j = it;
      for (; j > first && *(j - 1) > x; --j) *j = *(j - 1);
      *j = x;
    }
    for (Index* it = first; it != last;) {
      Index* jt = it + 1;
      while (jt != last && *jt == *it) ++jt;
      out.E(ne, 0) = a;
      out.E(ne, 1) = *it;
      out.face_count[ne] = static_cast<Index>(jt - it);
      ++ne;
      it = jt;
    }
  }
  out.E.conservativeResize(ne, 2);
  out.face_count.conservativeResize(ne);
  return out;
}

}  // namespace meshmark
