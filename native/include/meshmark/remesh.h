// meshmark: isotropic remeshing (CGAL Polygon_mesh_processing::isotropic_remeshing). The only
// meshmark translation unit with CGAL's remeshing code.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct RemeshedMesh {
  MatrixX3dR V;              // (n', 3) vertices of the result (unreferenced input vertices are dropped)
  MatrixX3iR T;              // (t', 3) triangles
  double target_edge_length;  // the length the remeshing aimed at (model units)
};

// Remeshes the surface of the triangles T towards edges of length `relative_length` x the mean
// length of its unique edges (CGAL's isotropic_remeshing: `iterations` rounds of splitting edges
// longer than 4/3 L, collapsing edges shorter than 4/5 L, flipping towards valence 6 and tangential
// relaxation; borders are remeshed, their vertices stay on the border). Deterministic.
// MeshError (never a crash) when the triangles are not an oriented 2-manifold (an edge shared by
// more than two triangles, a pinched vertex, orientations that cannot be made consistent), when a
// triangle is degenerate (zero area), when relative_length is not in (0, 100] or iterations not in
// 1..100, or when the target would make more than 20 million triangles.
RemeshedMesh remesh(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                    double relative_length, int iterations);

}  // namespace meshmark
