#include "meshmark/validate.h"
#include "meshmark/error.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace meshmark {

namespace {
std::string face_text(const PolygonsView& P, Offset f) {
  std::ostringstream s;
  s << "(";
  const Offset b = P.offsets[f], e = P.offsets[f + 1];
  for (Offset c = b; c < e && c < b + 8; ++c) s << (c > b ? ", " : "") << P.indices[c];
  if (e - b > 8) s << ", ...";
  s << ")";
  return s.str();
}
}  // namespace

void validate_vertices(const Eigen::Ref<const MatrixX3dR>& V) {
  if (V.rows() == 0) throw MeshError("mesh has no vertices");
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!(std::isfinite(V(i, 0)) && std::isfinite(V(i, 1)) && std::isfinite(V(i, 2)))) {
      std::ostringstream s;
      s << "vertex " << i << " has a non-finite coordinate (" << V(i, 0) << ", " << V(i, 1) << ", "
        << V(i, 2) << ")";
      throw MeshError(s.str());
    }
  }
}

void validate_polygons(Index n_vertices, const Polygons& P) {
  validate_polygons(n_vertices, PolygonsView{P.indices.data(), P.n_corners(), P.offsets.data(), P.n_faces()});
}

void validate_polygons(Index n_vertices, const PolygonsView& P) {
  const Offset m = P.n_faces;
  if (m <= 0) throw MeshError("mesh has no faces");
  if (P.offsets[0] != 0) throw MeshError("face offsets must start at 0");
  if (P.offsets[m] != P.n_corners) {
    std::ostringstream s;
    s << "face offsets end at " << P.offsets[m] << " but there are " << P.n_corners << " corners";
    throw MeshError(s.str());
  }
  for (Offset f = 0; f < m; ++f) {
    const Offset b = P.offsets[f], e = P.offsets[f + 1];
    if (e < b) {
      std::ostringstream s;
      s << "face offsets decrease at face " << f;
      throw MeshError(s.str());
    }
    if (e - b < 3) {
      std::ostringstream s;
      s << "face " << f << " has " << (e - b) << " vertices; a face needs at least 3";
      throw MeshError(s.str());
    }
    for (Offset c = b; c < e; ++c) {
      const Index v = P.indices[c];
      if (v < 0 || v >= n_vertices) {
        std::ostringstream s;
        s << "face " << f << " " << face_text(P, f) << " refers to vertex " << v << ", but the mesh has "
          << n_vertices << " vertices (valid indices are 0.." << (n_vertices - 1) << ")";
        throw MeshError(s.str());
      }
    }
    // Repeated vertex: faces are small, a quadratic scan is the fastest test; a large polygon (a
    // hostile file can hold one face of a million corners) is sorted instead: O(k log k).
    if (e - b > 64) {
      std::vector<Index> sorted(P.indices + b, P.indices + e);
      std::sort(sorted.begin(), sorted.end());
      const auto it = std::adjacent_find(sorted.begin(), sorted.end());
      if (it != sorted.end()) {
        std::ostringstream s;
        s << "face " << f << " " << face_text(P, f) << " repeats vertex " << *it;
        throw MeshError(s.str());
      }
      continue;
    }
    for (Offset c = b; c < e; ++c)
      for (Offset d = c + 1; d < e; ++d)
        if (P.indices[c] == P.indices[d]) {
          std::ostringstream s;
          s << "face " << f << " " << face_text(P, f) << " repeats vertex " << P.indices[c];
          throw MeshError(s.str());
        }
  }
}

void validate_mesh(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P) {
  validate_mesh(V, PolygonsView{P.indices.data(), P.n_corners(), P.offsets.data(), P.n_faces()});
}

void validate_mesh(const Eigen::Ref<const MatrixX3dR>& V, const PolygonsView& P) {
  validate_vertices(V);
  if (V.rows() > static_cast<Eigen::Index>(INT32_MAX)) throw MeshError("mesh has more than 2^31-1 vertices");
  validate_polygons(static_cast<Index>(V.rows()), P);
}

}  // namespace meshmark
