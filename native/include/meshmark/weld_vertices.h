// meshmark: merge vertices at exactly equal positions (split vertices).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/validate.h"

namespace meshmark {

struct Welded {
  VectorXi first;    // (k,) first input vertex of each welded vertex, increasing: welded vertices keep
                     // the order of first occurrence, so a mesh without duplicates maps to itself
  VectorXi map;      // (n,) welded vertex of each input vertex: V.row(i) == V.row(first[map[i]])
  VectorXi indices;  // corners of the kept faces, in welded vertex indices
  VectorXo offsets;  // (m'+1,) face offsets of the kept faces
  VectorXi face;     // (m',) input face of each kept face
  // When nothing merges (first.size() == n, map is the identity) the faces are unchanged and
  // indices, offsets and face are left EMPTY: the caller keeps its own faces (no copy).
};

// Welds the vertices of V whose three coordinates are exactly equal as doubles (so -0.0 == 0.0;
// V must be finite). Exporters split a vertex into coincident copies at UV seams and sharp edges,
// and non-indexed glTF/STL store every triangle corner separately; welding gives back the
// connected mesh whose edge graph the watermark methods need. Faces are reindexed: a corner equal
// to the previous one (cyclically) is removed, and a face left with fewer than 3 corners, or that
// still repeats a vertex, is dropped. Unreferenced vertices take part like any other.
// Open-addressing hash on the coordinate bits, O(n + c); O(n) when nothing merges.
Welded weld_vertices(const Eigen::Ref<const MatrixX3dR>& V, const PolygonsView& P);

}  // namespace meshmark
