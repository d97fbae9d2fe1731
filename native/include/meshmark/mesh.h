// meshmark: core types shared by every function of the native library.
#pragma once
#include <Eigen/Core>
#include <cstdint>

namespace meshmark {

using Index = std::int32_t;   // vertex, face and edge indices
using Offset = std::int64_t;  // offsets into flat corner arrays

using MatrixX3dR = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  // V: (n,3) float64
using MatrixX3iR = Eigen::Matrix<Index, Eigen::Dynamic, 3, Eigen::RowMajor>;   // T: (t,3) triangles
using MatrixX2iR = Eigen::Matrix<Index, Eigen::Dynamic, 2, Eigen::RowMajor>;   // E: (e,2) edges
using VectorXi = Eigen::Matrix<Index, Eigen::Dynamic, 1>;
using VectorXo = Eigen::Matrix<Offset, Eigen::Dynamic, 1>;
using VectorXb = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>;

// The faces of a polygon mesh (triangles, quads, n-gons mixed) as a flat list of corners:
// face f has the corners indices[offsets[f]] .. indices[offsets[f+1]-1], in winding order.
// This is the layout of Blender's loops/polygons and of PLY/OBJ face lists.
struct Polygons {
  VectorXi indices;  // (c,) vertex index of each corner
  VectorXo offsets;  // (m+1,) with offsets[0] == 0 and offsets[m] == c

  Offset n_faces() const { return offsets.size() > 0 ? offsets.size() - 1 : 0; }
  Offset n_corners() const { return indices.size(); }
  Index face_size(Offset f) const { return static_cast<Index>(offsets[f + 1] - offsets[f]); }
  Index corner(Offset f, Index k) const { return indices[offsets[f] + k]; }

  // Wraps a triangle (or any uniform k-gon) matrix; no validation.
  static Polygons from_triangles(const MatrixX3iR& T);
};

}  // namespace meshmark
