#include "meshmark/yang208_features.h"
#include "meshmark/edge_faces.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/face_normals.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/laplacian_coordinates.h"
#include "meshmark/laplacian_smooth.h"
#include "meshmark/unique_edges.h"
#include "meshmark/unit_cube_normalize.h"
#include "meshmark/vertex_adjacency.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace meshmark {

namespace {
void put8(Eigen::VectorXd& F, int j, const std::vector<double>& f) {
  const Eigen::Map<const Eigen::VectorXd> m(f.data(), static_cast<Eigen::Index>(f.size()));
  F.segment<4>(8 * j) = log_moments(m, kYang208LogFloor);  // eq. 8.1.4, first four
  F.segment<4>(8 * j + 4) = histogram_moments(m);          // eqs. 8.1.3-8.1.4, last four
}
}  // namespace

Eigen::VectorXd yang208_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  const VectorXb used = feature_mesh_check(V, T);
  const MatrixX3dR X = unit_cube_normalize(V, used);  // §8.1.1
  const EdgeList edges = unique_edges(n, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(n, edges.E);
  const MatrixX3dR Xs = laplacian_smooth(X, A, 1.0, 1);  // M' (§8.1.2): x - D^-1 R x
  const MatrixX3dR L = laplacian_coordinates(X, A, 0.0), Ls = laplacian_coordinates(Xs, A, 0.0);  // R x, eq. 8.1.2

  std::vector<char> interior(n, 1);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e)
    if (edges.face_count[e] != 2) interior[edges.E(e, 0)] = interior[edges.E(e, 1)] = 0;

  Eigen::VectorXd F = Eigen::VectorXd::Zero(kYang208Size);
  std::array<std::vector<double>, 24> vv;
  for (auto& v : vv) v.reserve(n);
  for (Index i = 0; i < n; ++i) {
    const Offset val = A.ptr[i + 1] - A.ptr[i];
    if (!used[i] || !interior[i] || val == 0) continue;
    const int c = val < 6 ? 0 : (val == 6 ? 1 : 2);  // §8.1.3: valence < 6, = 6, > 6
    std::vector<double>* b = &vv[8 * c];
    const Eigen::RowVector3d d = X.row(i) - Xs.row(i), dl = L.row(i) - Ls.row(i);
    for (int k = 0; k < 3; ++k) b[k].push_back(std::abs(d[k]));
    b[3].push_back(d.norm());
    for (int k = 0; k < 3; ++k) b[4 + k].push_back(std::abs(dl[k]));
    b[7].push_back(std::abs(L.row(i).norm() - Ls.row(i).norm()));
  }
  for (int j = 0; j < 24; ++j) put8(F, j, vv[j]);

  // dihedral angles (angle between the normals of the two faces of an interior edge) of M and M'
  const MatrixX3dR N = face_normals(X, T), Ns = face_normals(Xs, T);
  const EdgeFaces EF = edge_faces(edges, A, T);
  auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); };
  std::vector<double> dih;
  dih.reserve(edges.E.rows());
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    if (edges.face_count[e] != 2 || EF.f1[e] < 0) continue;
    const Index f0 = EF.f0[e], f1 = EF.f1[e];
    if (N.row(f0).squaredNorm() == 0 || N.row(f1).squaredNorm() == 0 || Ns.row(f0).squaredNorm() == 0 ||
        Ns.row(f1).squaredNorm() == 0)
      continue;  // a degenerate face has no normal
    dih.push_back(std::abs(angle(N.row(f0), N.row(f1)) - angle(Ns.row(f0), Ns.row(f1))));
  }
  put8(F, 24, dih);

  std::vector<double> fa;
  fa.reserve(T.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d a = N.row(f), b = Ns.row(f);
    if (a.squaredNorm() == 0 || b.squaredNorm() == 0) continue;  // degenerate face: no normal
    fa.push_back(angle(a, b));
  }
  put8(F, 25, fa);
  return F;
}

}  // namespace meshmark
