#include "meshmark/closest_points.h"
#include "meshmark/error.h"
#include "meshmark/parallel_for.h"
#include "meshmark/triangle_tree.h"

namespace meshmark {

ClosestPoints closest_points(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& V,
                             const Eigen::Ref<const MatrixX3iR>& T) {
  if (T.rows() == 0) throw MeshError("closest points: the mesh has no triangles");
  return closest_points(P, TriangleTree(V, T));
}

ClosestPoints closest_points(const Eigen::Ref<const MatrixX3dR>& P, const TriangleTree& tree) {
  if (tree.size() == 0) throw MeshError("closest points: the mesh has no triangles");
  const Eigen::Index m = P.rows();
  ClosestPoints r;
  r.Q.resize(m, 3);
  r.face.resize(m);
  r.bary.resize(m, 3);
  r.d2.resize(m);
  parallel_for(m, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      Index f;
      Eigen::Vector3d q, w;
      r.d2[i] = tree.closest_point(P.row(i).transpose(), &f, &q, &w);
      r.Q.row(i) = q.transpose();
      r.bary.row(i) = w.transpose();
      r.face[i] = f;
    }
  });
  return r;
}

}  // namespace meshmark
