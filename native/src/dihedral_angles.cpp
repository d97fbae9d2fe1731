#include "meshmark/dihedral_angles.h"
#include "meshmark/face_normals.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

namespace meshmark {

DihedralAngles dihedral_angles(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  DihedralAngles D;
  const Polygons P = Polygons::from_triangles(T);
  D.edges = unique_edges(static_cast<Index>(V.rows()), P);
  const Eigen::Index ne = D.edges.E.rows();
  const MatrixX3dR N = face_normals(V, T);
  // The two faces of each edge, found by binary search in the sorted edge list.
  std::vector<Index> f0(ne, -1), f1(ne, -1);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      Index a = T(f, k), b = T(f, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      Eigen::Index lo = 0, hi = ne;
      while (lo < hi) {
        const Eigen::Index mid = (lo + hi) / 2;
        if (D.edges.E(mid, 0) < a || (D.edges.E(mid, 0) == a && D.edges.E(mid, 1) < b)) lo = mid + 1;
        else hi = mid;
      }
      (f0[lo] < 0 ? f0[lo] : f1[lo]) = static_cast<Index>(f);
    }
  }
  D.angle.resize(ne);
  for (Eigen::Index e = 0; e < ne; ++e) {
    if (D.edges.face_count[e] != 2) {
      D.angle[e] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const Eigen::Vector3d n0 = N.row(f0[e]), n1 = N.row(f1[e]);
    D.angle[e] = std::atan2(n0.cross(n1).norm(), n0.dot(n1));
  }
  return D;
}

}  // namespace meshmark
