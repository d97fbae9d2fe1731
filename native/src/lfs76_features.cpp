#include "meshmark/lfs76_features.h"
#include "meshmark/error.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/pca_min_corner_normalize.h"
#include "meshmark/rusinkiewicz_curvatures.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace meshmark {

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();  // MATLAB's eps, 2^-52
using R3 = Eigen::RowVector3d;

struct Graph {  // triangulation2adjacency: every ordered pair of corners of a face (self-pairs of degenerate faces too)
  std::vector<std::vector<Index>> nbr;  // sorted, unique
};

Graph adjacency(Eigen::Index n, const Eigen::Ref<const MatrixX3iR>& T) {
  Graph g;
  g.nbr.assign(n, {});
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (a != b) g.nbr[T(f, a)].push_back(T(f, b));
  for (auto& v : g.nbr) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  return g;
}

// (D - W) x, the unnormalised graph Laplacian of the adjacency.
MatrixX3dR kirchhoff(const Graph& g, const MatrixX3dR& X) {
  MatrixX3dR L(X.rows(), 3);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    R3 s = R3::Zero();
    for (const Index j : g.nbr[i]) s += X.row(j);
    L.row(i) = static_cast<double>(g.nbr[i].size()) * X.row(i) - s;
  }
  return L;
}

// perform_mesh_heat_diffusion: x <- x - dt (I - D^-1 W) x; a vertex without neighbours (an empty row of
// D^-1 W) decays as x <- (1 - dt) x.
MatrixX3dR heat_diffusion(const Graph& g, MatrixX3dR X, double dt, int steps) {
  for (int it = 0; it < steps; ++it) {
    MatrixX3dR Y(X.rows(), 3);
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      R3 s = R3::Zero();
      const double inv = g.nbr[i].empty() ? 0.0 : 1.0 / static_cast<double>(g.nbr[i].size());
      for (const Index j : g.nbr[i]) s += inv * X.row(j);
      Y.row(i) = X.row(i) - dt * (X.row(i) - s);
    }
    X = std::move(Y);
  }
  return X;
}

double angle(const R3& a, const R3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }  // vectorAngle3d

MatrixX3dR face_normal_geom3d(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T) {  // faceNormal
  MatrixX3dR N(T.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const R3 a = X.row(T(f, 1)) - X.row(T(f, 0)), b = X.row(T(f, 2)) - X.row(T(f, 0));
    N.row(f) = (a / a.norm()).cross(b / b.norm());
  }
  return N;
}

MatrixX3dR vertex_normals_max(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T, const MatrixX3dR& N) {
  MatrixX3dR VN = MatrixX3dR::Zero(X.rows(), 3);  // CalcVertexNormals(FV, N), N = faceNormal (not unit)
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const R3 v0 = X.row(T(f, 0)), v1 = X.row(T(f, 1)), v2 = X.row(T(f, 2));
    const double de0 = (v2 - v1).norm(), de1 = (v0 - v2).norm(), de2 = (v1 - v0).norm();
    const double s = (de0 + de1 + de2) / 2, heron = s * (s - de0) * (s - de1) * (s - de2);
    const double Af = heron > 0 ? std::sqrt(heron) : 0.0;
    VN.row(T(f, 0)) += Af / (de1 * de1 * de2 * de2) * N.row(f);
    VN.row(T(f, 1)) += Af / (de0 * de0 * de2 * de2) * N.row(f);
    VN.row(T(f, 2)) += Af / (de1 * de1 * de0 * de0) * N.row(f);
  }
  for (Eigen::Index i = 0; i < VN.rows(); ++i) VN.row(i) /= VN.row(i).norm();
  return VN;
}

struct Spherical {
  Eigen::VectorXd az, el, rho;
};

Spherical enu2aer(const MatrixX3dR& X) {  // about the mean of all vertices, degrees
  const R3 o = X.colwise().mean();
  Spherical s;
  s.az.resize(X.rows()), s.el.resize(X.rows()), s.rho.resize(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double e = X(i, 0) - o[0], nn = X(i, 1) - o[1], u = X(i, 2) - o[2];
    const double r = std::hypot(e, nn);
    s.rho[i] = std::hypot(r, u);
    s.el[i] = std::atan2(u, r) * (180.0 / M_PI);
    double az = std::fmod(std::atan2(e, nn), 2 * M_PI);  // mod(x, 2 pi): the sign of the divisor
    if (az < 0) az += 2 * M_PI;
    s.az[i] = az * (180.0 / M_PI);
  }
  return s;
}

std::vector<std::pair<Index, Index>> mesh_edges(const Eigen::Ref<const MatrixX3iR>& T) {  // meshEdges: (small, large)
  std::vector<std::pair<Index, Index>> e;
  e.reserve(3 * T.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index a = T(f, k), b = T(f, (k + 1) % 3);
      e.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

// The log-moments of x (already + eps); MATLAB's NaN statistics (constant x, NaN entries) are 0.
Eigen::Vector4d stats(const std::vector<double>& x) {
  for (const double v : x)
    if (std::isnan(v)) return Eigen::Vector4d::Zero();
  std::vector<double> y(x.size());
  for (size_t i = 0; i < x.size(); ++i) y[i] = std::log(x[i]);
  return moments4(Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(y.size())));
}

double plus_eps(double d) { return std::isnan(d) ? kEps : d + kEps; }
}  // namespace

Eigen::VectorXd lfs76_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                               double dt, double t_max) {
  if (!(dt > 0) || !(t_max >= dt))
    throw MeshError("LFS76 needs dt > 0 and t_max >= dt, got dt=" + std::to_string(dt) + ", t_max=" +
                    std::to_string(t_max));
  feature_mesh_check(V, T);
  const Eigen::Index n = V.rows(), nf = T.rows();
  const Graph g = adjacency(n, T);
  const MatrixX3dR Vs = heat_diffusion(g, V, dt, static_cast<int>(std::lround(t_max / dt)));
  const MatrixX3dR Xo = pca_min_corner_normalize(V), Xs = pca_min_corner_normalize(Vs);
  std::vector<std::vector<double>> v(19);  // 0-2 position, 3 norm, 4-6 Laplacian, 7 its norm, 8-18 as below
  const MatrixX3dR Lo = kirchhoff(g, Xo), Ls = kirchhoff(g, Xs);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) v[k].push_back(plus_eps(std::abs(Xo(i, k) - Xs(i, k))));
    v[3].push_back(plus_eps(std::abs(Xo.row(i).norm() - Xs.row(i).norm())));
    for (int k = 0; k < 3; ++k) v[4 + k].push_back(plus_eps(std::abs(Lo(i, k) - Ls(i, k))));
    v[7].push_back(plus_eps(std::abs(Lo.row(i).norm() - Ls.row(i).norm())));
  }
  const MatrixX3dR No = face_normal_geom3d(Xo, T), Ns = face_normal_geom3d(Xs, T);
  for (Eigen::Index f = 0; f < nf; ++f) v[8].push_back(plus_eps(angle(No.row(f), Ns.row(f))));
  // 37-40: meshDihedralAngles over meshEdges; meshEdgeFaces puts the last face with side (small -> large)
  // in column 1 and the last with (large -> small) in column 2
  const auto edges = mesh_edges(T);
  std::vector<Index> c1(edges.size(), -1), c2(edges.size(), -1);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const Index a = T(f, k), b = T(f, (k + 1) % 3);
      if (a == b) continue;
      const size_t e = std::lower_bound(edges.begin(), edges.end(), std::make_pair(std::min(a, b), std::max(a, b))) -
                       edges.begin();
      (a < b ? c1 : c2)[e] = static_cast<Index>(f);
    }
  for (size_t e = 0; e < edges.size(); ++e)
    if (c1[e] >= 0 && c2[e] >= 0)  // the published code fails otherwise (face index 0)
      v[9].push_back(plus_eps(std::abs(angle(No.row(c1[e]), No.row(c2[e])) - angle(Ns.row(c1[e]), Ns.row(c2[e])))));
  const MatrixX3dR VNo = vertex_normals_max(Xo, T, No), VNs = vertex_normals_max(Xs, T, Ns);
  const PrincipalCurvatures ko = rusinkiewicz_curvatures(Xo, T), ks = rusinkiewicz_curvatures(Xs, T);
  auto ratio = [](double a, double b) { return std::min(std::abs(a), std::abs(b)) / std::max(std::abs(a), std::abs(b)); };
  const Spherical so = enu2aer(Xo), ss = enu2aer(Xs);
  for (Eigen::Index i = 0; i < n; ++i) {
    v[10].push_back(plus_eps(angle(VNo.row(i), VNs.row(i))));
    v[11].push_back(plus_eps(std::abs(ko.k1[i] * ko.k2[i] - ks.k1[i] * ks.k2[i])));
    v[12].push_back(plus_eps(std::abs(ratio(ko.k1[i], ko.k2[i]) - ratio(ks.k1[i], ks.k2[i]))));
    v[13].push_back(plus_eps(std::abs(so.az[i] - ss.az[i])));
    v[14].push_back(plus_eps(std::abs(so.el[i] - ss.el[i])));
    v[15].push_back(plus_eps(std::abs(so.rho[i] - ss.rho[i])));
  }
  for (const auto& [a, b] : edges) {
    v[16].push_back(plus_eps(std::abs(std::abs(so.az[a] - so.az[b]) - std::abs(ss.az[a] - ss.az[b]))));
    v[17].push_back(plus_eps(std::abs(std::abs(so.el[a] - so.el[b]) - std::abs(ss.el[a] - ss.el[b]))));
    v[18].push_back(plus_eps(std::abs(std::abs(so.rho[a] - so.rho[b]) - std::abs(ss.rho[a] - ss.rho[b]))));
  }
  Eigen::VectorXd F(kLfs76Size);
  for (int grp = 0; grp < 2; ++grp)  // 1-12 and 17-28: [mean x y z, var x y z, skew x y z, kurt x y z]
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector4d s = stats(v[4 * grp + k]);
      for (int st = 0; st < 4; ++st) F[16 * grp + 3 * st + k] = s[st];
    }
  F.segment<4>(12) = stats(v[3]);
  F.segment<4>(28) = stats(v[7]);
  for (int j = 8; j < 19; ++j) F.segment<4>(32 + 4 * (j - 8)) = stats(v[j]);
  return F;
}

}  // namespace meshmark
