#include "meshmark/yang208_features.h"
#include "meshmark/edge_faces.h"
#include "meshmark/face_normal_noise.h"
#include "meshmark/face_normals.h"
#include "meshmark/feature_frame.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/laplacian_coordinates.h"
#include "meshmark/laplacian_smooth.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <vector>

namespace meshmark {

namespace {
void put8(Eigen::VectorXd& F, int j, const NoisyVector& v) {
  F.segment<4>(8 * j) = floored_log_moments(v, kYang208Cap);  // eq. 8.1.4, first four
  const std::vector<double> x = floored_values(v, kYang208Cap);
  F.segment<4>(8 * j + 4) = histogram_moments(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())));
}
double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }
}  // namespace

Eigen::VectorXd yang208_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  const VectorXb used = feature_mesh_check(V, T);
  const FeatureFrame fr = feature_frame(V, used);  // §8.1.1, canonical where the axes are not determined
  const MatrixX3dR& X = fr.X;
  const EdgeList edges = unique_edges(n, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(n, edges.E);
  const MatrixX3dR Xs = laplacian_smooth(X, A, 1.0, 1);  // M' (§8.1.2): x - D^-1 R x
  const MatrixX3dR L = laplacian_coordinates(X, A, 0.0), Ls = laplacian_coordinates(Xs, A, 0.0);  // R x, eq. 8.1.2

  std::vector<char> interior(n, 1);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e)
    if (edges.face_count[e] != 2) interior[edges.E(e, 0)] = interior[edges.E(e, 1)] = 0;

  // noise bounds per unit of vertex noise (feature_statistics.h): x and x' = mean of neighbours move by <= u
  const double u = kStorageUnit, r3 = std::sqrt(3.0);
  Eigen::VectorXd F = Eigen::VectorXd::Zero(kYang208Size);
  std::array<NoisyVector, 24> vv;
  for (auto& v : vv) v.reserve(n);
  for (Index i = 0; i < n; ++i) {
    const Offset val = A.ptr[i + 1] - A.ptr[i];
    if (!used[i] || !interior[i] || val == 0) continue;
    const int c = val < 6 ? 0 : (val == 6 ? 1 : 2);  // §8.1.3: valence < 6, = 6, > 6
    NoisyVector* b = &vv[8 * c];
    const Eigen::RowVector3d d = X.row(i) - Xs.row(i), dl = L.row(i) - Ls.row(i);
    const Eigen::RowVector3d pd = pooled_abs(fr, d), pl = pooled_abs(fr, dl);
    const double k = static_cast<double>(val);
    for (int a = 0; a < 3; ++a) b[a].push(pd[a], 2 * u);
    b[3].push(d.norm(), 2 * r3 * u);
    for (int a = 0; a < 3; ++a) b[4 + a].push(pl[a], 4 * k * u);  // (R (x - x'))_a: 2k terms of <= 2u
    b[7].push(std::abs(L.row(i).norm() - Ls.row(i).norm()), 4 * r3 * k * u);
  }
  for (int j = 0; j < 24; ++j) put8(F, j, vv[j]);

  // dihedral angles (angle between the normals of the two faces of an interior edge) of M and M'
  const MatrixX3dR N = face_normals(X, T), Ns = face_normals(Xs, T);
  const Eigen::VectorXd nu = face_normal_noise(X, T), nus = face_normal_noise(Xs, T);
  const EdgeFaces EF = edge_faces(edges, A, T);
  NoisyVector dih, fa;
  dih.reserve(edges.E.rows());
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    if (edges.face_count[e] != 2 || EF.f1[e] < 0) continue;
    const Index f0 = EF.f0[e], f1 = EF.f1[e];
    dih.push(std::abs(angle(N.row(f0), N.row(f1)) - angle(Ns.row(f0), Ns.row(f1))),
             u * (nu[f0] + nu[f1] + nus[f0] + nus[f1]));  // a degenerate face: +inf, left out
  }
  put8(F, 24, dih);
  fa.reserve(T.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f) fa.push(angle(N.row(f), Ns.row(f)), u * (nu[f] + nus[f]));
  put8(F, 25, fa);
  return F;
}

}  // namespace meshmark
