#include "meshmark/lfs76_features.h"
#include "meshmark/angle_sum.h"
#include "meshmark/edge_faces.h"
#include "meshmark/error.h"
#include "meshmark/face_areas.h"
#include "meshmark/face_normals.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/interior_angles.h"
#include "meshmark/laplacian_coordinates.h"
#include "meshmark/laplacian_smooth.h"
#include "meshmark/unique_edges.h"
#include "meshmark/unit_cube_normalize.h"
#include "meshmark/vertex_adjacency.h"
#include "meshmark/vertex_normals.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace meshmark {

namespace {
// log(|d| + eps): the published eps = 2^-52 is at the rounding level of the differences, and exact
// zeros (coplanar faces) against 1e-16 noise moved log-moments by up to 0.8 under a rotation (vhacd_hero);
// eps = kFeatureLogFloor (1e-7 unit-cube lengths / radians; 1e-7 rad in degrees for the spherical angles).
constexpr double kLogFloor = kFeatureLogFloor;
constexpr double kLogFloorDeg = kFeatureLogFloor * 180.0 / M_PI;

void put4(Eigen::VectorXd& F, int j, const std::vector<double>& f) {
  const bool degrees = j == 13 || j == 14 || j == 16 || j == 17;  // spherical az / elev and their edge differences
  F.segment<4>(4 * j) = log_moments(Eigen::Map<const Eigen::VectorXd>(f.data(), static_cast<Eigen::Index>(f.size())),
                                    degrees ? -kLogFloorDeg : -kLogFloor);  // log(|d| + eps)
}

double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

double wrap_deg(double d) {  // |difference of two azimuths| in [0, 180]
  d = std::fmod(std::abs(d), 360.0);
  return d > 180.0 ? 360.0 - d : d;
}

// Gaussian curvature and curvature ratio (Meyer et al., barycentric areas) per vertex.
void curvatures(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T, Eigen::VectorXd& K, Eigen::VectorXd& R,
                std::vector<char>& ok) {
  const Eigen::Index n = X.rows();
  const Eigen::VectorXd asum = angle_sum(X, T), area = face_areas(X, T);
  const auto ang = interior_angles(X, T);
  Eigen::VectorXd A = Eigen::VectorXd::Zero(n);
  MatrixX3dR Hn = MatrixX3dR::Zero(n, 3);
  Eigen::VectorXd Hs = Eigen::VectorXd::Zero(n);  // sum of the magnitudes that make up Hn (its rounding scale)
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index a = T(f, k), b = T(f, (k + 1) % 3), c = T(f, (k + 2) % 3);
      A[a] += area[f] / 3;
      const double s = std::sin(ang(f, k));
      if (s <= 0) continue;
      const double cot = std::cos(ang(f, k)) / s;  // angle at a, opposite edge (b, c)
      const Eigen::RowVector3d d = X.row(b) - X.row(c);
      Hn.row(b) += cot * d;
      Hn.row(c) -= cot * d;
      Hs[b] += std::abs(cot) * d.norm();
      Hs[c] += std::abs(cot) * d.norm();
    }
  K.resize(n);
  R.resize(n);
  ok.assign(n, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(A[i] > 0)) continue;
    // flat vertices: a deficit or mean-curvature normal at the rounding level is 0 (else the noise,
    // divided by a small area, dominates the log-moments and breaks the invariance)
    double deficit = 2 * M_PI - asum[i];
    if (std::abs(deficit) < 1e-12) deficit = 0;
    K[i] = deficit / A[i];
    const double hn = Hn.row(i).norm();
    const double H = hn <= 1e-12 * Hs[i] ? 0.0 : hn / (4 * A[i]);
    const double disc = std::sqrt(std::max(H * H - K[i], 0.0));
    const double k1 = std::abs(H + disc), k2 = std::abs(H - disc), mx = std::max(k1, k2);
    R[i] = mx > 0 ? std::min(k1, k2) / mx : 0.0;
    ok[i] = 1;
  }
}

void spherical(const MatrixX3dR& X, const VectorXb& used, Eigen::VectorXd& az, Eigen::VectorXd& el,
               Eigen::VectorXd& rho) {
  Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
  double m = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (used[i]) c += X.row(i), m += 1;
  c /= m;
  const Eigen::Index n = X.rows();
  az.resize(n), el.resize(n), rho.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {  // enu2aer with (e, n, u) = (x, y, z), degrees
    const Eigen::RowVector3d d = X.row(i) - c;
    const double h = std::hypot(d[0], d[1]);
    az[i] = std::atan2(d[0], d[1]) * 180.0 / M_PI;
    el[i] = std::atan2(d[2], h) * 180.0 / M_PI;
    rho[i] = d.norm();
  }
}
}  // namespace

Eigen::VectorXd lfs76_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                               double dt, double t_max) {
  if (!(dt > 0) || !(t_max >= dt))
    throw MeshError("LFS76 needs dt > 0 and t_max >= dt, got dt=" + std::to_string(dt) + ", t_max=" +
                    std::to_string(t_max));
  const Index n = static_cast<Index>(V.rows());
  const VectorXb used = feature_mesh_check(V, T);
  const MatrixX3dR X = unit_cube_normalize(V, used);  // one similarity for both meshes
  const EdgeList edges = unique_edges(n, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(n, edges.E);
  const int steps = static_cast<int>(std::lround(t_max / dt));
  const MatrixX3dR Xs = laplacian_smooth(X, A, dt, steps);  // heat diffusion, I - D^-1 W, explicit
  const MatrixX3dR L = laplacian_coordinates(X, A, 0.0), Ls = laplacian_coordinates(Xs, A, 0.0);

  std::vector<char> interior(n, 1);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e)
    if (edges.face_count[e] != 2) interior[edges.E(e, 0)] = interior[edges.E(e, 1)] = 0;

  Eigen::VectorXd F = Eigen::VectorXd::Zero(kLfs76Size);
  std::vector<std::vector<double>> v(19);
  for (auto& x : v) x.reserve(n);
  const Eigen::RowVector3d c(0.5, 0.5, 0.5);
  const MatrixX3dR VN = vertex_normals(X, T), VNs = vertex_normals(Xs, T);
  for (Index i = 0; i < n; ++i) {
    if (!used[i]) continue;
    const Eigen::RowVector3d d = X.row(i) - Xs.row(i), dl = L.row(i) - Ls.row(i);
    for (int k = 0; k < 3; ++k) v[k].push_back(std::abs(d[k]));
    v[3].push_back(std::abs((X.row(i) - c).norm() - (Xs.row(i) - c).norm()));
    for (int k = 0; k < 3; ++k) v[4 + k].push_back(std::abs(dl[k]));
    v[7].push_back(std::abs(L.row(i).norm() - Ls.row(i).norm()));
    if (VN.row(i).squaredNorm() > 0 && VNs.row(i).squaredNorm() > 0) v[10].push_back(angle(VN.row(i), VNs.row(i)));
  }
  const MatrixX3dR N = face_normals(X, T), Ns = face_normals(Xs, T);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    if (N.row(f).squaredNorm() > 0 && Ns.row(f).squaredNorm() > 0) v[8].push_back(angle(N.row(f), Ns.row(f)));
  const EdgeFaces EF = edge_faces(edges, A, T);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    if (edges.face_count[e] != 2 || EF.f1[e] < 0) continue;
    const Index f0 = EF.f0[e], f1 = EF.f1[e];
    if (N.row(f0).squaredNorm() == 0 || N.row(f1).squaredNorm() == 0 || Ns.row(f0).squaredNorm() == 0 ||
        Ns.row(f1).squaredNorm() == 0)
      continue;
    v[9].push_back(std::abs(angle(N.row(f0), N.row(f1)) - angle(Ns.row(f0), Ns.row(f1))));
  }
  Eigen::VectorXd K, R, Ks, Rs;
  std::vector<char> ok, oks;
  curvatures(X, T, K, R, ok);
  curvatures(Xs, T, Ks, Rs, oks);
  for (Index i = 0; i < n; ++i)
    if (used[i] && interior[i] && ok[i] && oks[i]) {
      v[11].push_back(std::abs(K[i] - Ks[i]));
      v[12].push_back(std::abs(R[i] - Rs[i]));
    }
  Eigen::VectorXd az, el, rho, azs, els, rhos;
  spherical(X, used, az, el, rho);
  spherical(Xs, used, azs, els, rhos);
  for (Index i = 0; i < n; ++i)
    if (used[i]) {
      v[13].push_back(wrap_deg(az[i] - azs[i]));
      v[14].push_back(std::abs(el[i] - els[i]));
      v[15].push_back(std::abs(rho[i] - rhos[i]));
    }
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    const Index a = edges.E(e, 0), b = edges.E(e, 1);
    v[16].push_back(std::abs(wrap_deg(az[a] - az[b]) - wrap_deg(azs[a] - azs[b])));
    v[17].push_back(std::abs(std::abs(el[a] - el[b]) - std::abs(els[a] - els[b])));
    v[18].push_back(std::abs(std::abs(rho[a] - rho[b]) - std::abs(rhos[a] - rhos[b])));
  }
  // Feature order of the published LFS76_fea.m: 1-12 cartesian components, 13-16 norm, 17-28 Laplacian
  // components, 29-32 Laplacian norm, 33 face normals, 37 dihedral, 41 vertex normals, 45 Gaussian
  // curvature, 49 curvature ratio, 53 az, 57 elev, 61 rho, 65 edge az, 69 edge elev, 73 edge rho.
  // Published 1-12 are [mean(x,y,z), var(x,y,z), ...] (moments grouped by statistic); here by vector.
  for (int j = 0; j < 19; ++j) put4(F, j, v[j]);
  return F;
}

}  // namespace meshmark
