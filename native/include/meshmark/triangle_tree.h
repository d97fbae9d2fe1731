// meshmark: exact closest-point queries on a triangle set (bounding-volume hierarchy).
#pragma once
#include "meshmark/mesh.h"
#include <vector>

namespace meshmark {

// An axis-aligned bounding-box tree over the triangles of (V, T), built by median splits on the
// longest axis of the centroid box (leaves of at most 4 triangles). Queries are exact: the distance
// from p to the closed triangle set, with Ericson's closest-point-on-triangle (Real-Time Collision
// Detection 5.1.5). The tree keeps a copy of the triangle corners; V and T may be dropped after.
class TriangleTree {
 public:
  TriangleTree(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

  // Squared distance from p to the nearest triangle and its index (-1 if the tree is empty).
  double closest(const Eigen::Vector3d& p, Index* face = nullptr) const;

  // The nearest point q on the triangle set (exact, as closest()), its triangle and barycentric
  // coordinates (q = b0 a + b1 b + b2 c of T's corners); returns the squared distance.
  double closest_point(const Eigen::Vector3d& p, Index* face, Eigen::Vector3d* q, Eigen::Vector3d* bary = nullptr) const;

  // Squared distance from p to one triangle, by its index in T.
  double face_distance2(Index face, const Eigen::Vector3d& p) const;

  // The triangles whose bounding boxes meet the box [lo, hi] (ids in T, in no particular order);
  // false (out incomplete) when there are more than `limit`.
  bool overlapping(const double* lo, const double* hi, std::vector<Index>& out, std::size_t limit) const;

  Eigen::Index size() const { return static_cast<Eigen::Index>(tri_.size()); }

  // (t, 3) unit normals (b - a) x (c - a) / |.| of the triangles, in T's order (zero rows for
  // degenerate triangles).
  MatrixX3dR face_normals() const;

 private:
  struct Node {
    float lo[3], hi[3];     // box (rounded outwards to float)
    std::int32_t left;      // internal: index of the left child (right = left + 1); leaf: -1
    std::int32_t first;     // leaf: first triangle in tri_
    std::int32_t count;     // leaf: number of triangles
    std::int32_t pad;
  };
  struct Tri {
    double a[3], ab[3], ac[3];
    Index id;
  };
  std::vector<Node> nodes_;
  std::vector<Tri> tri_;
  std::vector<std::int32_t> pos_;  // triangle index in T -> position in tri_
};

}  // namespace meshmark
