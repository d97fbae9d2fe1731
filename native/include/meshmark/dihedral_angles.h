// meshmark: dihedral angles of a triangle mesh.
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/unique_edges.h"

namespace meshmark {

struct DihedralAngles {
  EdgeList edges;          // unique edges of the triangle mesh (diagonals of split polygons included)
  Eigen::VectorXd angle;   // (e,) angle in radians between the normals of the two faces of each edge:
                           // 0 for coplanar faces, pi for a fold. NaN on boundary and non-manifold edges.
};

DihedralAngles dihedral_angles(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
