// meshmark: the nearest surface point of many query points (informed tracing's resampling).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/triangle_tree.h"

namespace meshmark {

struct ClosestPoints {
  MatrixX3dR Q;        // (m,3) nearest point of (V, T) to each query
  VectorXi face;       // (m,) its triangle
  MatrixX3dR bary;     // (m,3) barycentric weights of the triangle's corners (Q = sum_k bary_k V[T(face,k)])
  Eigen::VectorXd d2;  // (m,) squared distance
};

// Exact closest points of each row of P on the triangle set (V, T) (TriangleTree; both query threads
// share one tree). MeshError when T is empty.
ClosestPoints closest_points(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& V,
                             const Eigen::Ref<const MatrixX3iR>& T);
// The same on a tree built once.
ClosestPoints closest_points(const Eigen::Ref<const MatrixX3dR>& P, const TriangleTree& tree);

}  // namespace meshmark
