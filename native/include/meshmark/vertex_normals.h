// meshmark: per-vertex unit normals of a triangle mesh.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// n_i = normalize(sum over incident triangles of (b - a) x (c - a)) (area-weighted face normals).
// Vertices with a zero sum (unreferenced, or only degenerate incident triangles) get (0, 0, 0).
MatrixX3dR vertex_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
