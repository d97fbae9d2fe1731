// meshmark: deterministic triangulation of polygon faces.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct Triangulation {
  MatrixX3iR T;    // (t,3) triangles, same winding as their polygon
  VectorXi face;   // (t,) index of the source polygon of each triangle
};

// Triangles are copied. Polygons of up to 64 corners are ear-clipped in the plane of their Newell
// normal, scanning corners in order and clipping the first ear found (for a convex polygon this is
// the fan from corner 0: (0,1,2), (0,2,3), ...). A quad whose 0-2 diagonal lies outside it is split
// on 1-3. Degenerate polygons where no ear exists fall back to the fan. Larger polygons: a strictly
// convex one is the same fan; any other goes to ear_clip_polygon (grid index, about O(k log k)).
// Always sum(k - 2) triangles using every corner. See docs/mesh_model.md.
Triangulation triangulate(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P);

}  // namespace meshmark
