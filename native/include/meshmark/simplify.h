// meshmark: edge-collapse simplification (CGAL Surface_mesh_simplification, Garland-Heckbert
// quadric error metric). The only meshmark translation unit with CGAL's simplification code.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct SimplifiedMesh {
  MatrixX3dR V;  // (n', 3) vertices of the result (unreferenced input vertices are dropped)
  MatrixX3iR T;  // (t', 3) triangles
};

// Collapses edges, cheapest quadric error first, with the quadric-optimal vertex placement, until
// at most round(fraction * t) triangles remain (or no collapse is possible). The triangles T are
// oriented and made manifold first (non-manifold vertices duplicated, CGAL PMP orient_polygon_soup).
// MeshError if fraction is not in (0, 1] or if round(fraction * t) < 4 (too small to simplify).
SimplifiedMesh simplify(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T, double fraction);

}  // namespace meshmark
