// meshmark: the cropping attack: cut the mesh with a plane.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct CroppedMesh {
  MatrixX3dR V;   // kept vertices, in their original order
  Polygons P;     // kept faces, in their original order, re-indexed
  VectorXi kept;  // (n',) original index of each kept vertex
};

// s_i = v_i . normal (normal normalized), over the vertices referenced by P; threshold
// thr = max(s) - fraction (max(s) - min(s)). A face is kept iff every corner has s <= thr (faces are
// not cut, so polygons stay polygons); vertices no kept face uses are removed.
// MeshError if fraction is not in [0, 1), normal is zero, or nothing would remain.
CroppedMesh crop_plane(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P, const Eigen::Vector3d& normal,
                       double fraction);

}  // namespace meshmark
