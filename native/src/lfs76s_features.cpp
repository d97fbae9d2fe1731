#include "meshmark/lfs76s_features.h"
#include "meshmark/edge_faces.h"
#include "meshmark/error.h"
#include "meshmark/face_normal_noise.h"
#include "meshmark/face_normals.h"
#include "meshmark/feature_frame.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/laplacian_coordinates.h"
#include "meshmark/laplacian_smooth.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace meshmark {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = 180.0 / M_PI;
constexpr double kCap = 0.1;                 // lengths (unit cube), radians, the curvature ratio
constexpr double kCapDeg = kCap * kDeg;      // the spherical angles, degrees
const double kR3 = std::sqrt(3.0), kU = kStorageUnit;
using R3 = Eigen::RowVector3d;

double angle(const R3& a, const R3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

double wrap_deg(double d) {  // |difference of two azimuths| in [0, 180]
  d = std::fmod(std::abs(d), 360.0);
  return d > 180.0 ? 360.0 - d : d;
}

struct Curv {  // per vertex: Gaussian curvature, curvature ratio and their noise bounds (per unit vertex noise)
  Eigen::VectorXd K, bK, R, bR;
};

// Meyer et al.'s operators with barycentric areas: K = (2 pi - sum theta) / A, H = |sum cot (x_b - x_c)| / (4 A),
// k = H +- sqrt(max(H^2 - K, 0)), ratio min|k| / max|k|; first-order bounds of each under vertex noise u.
Curv curvatures(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index n = X.rows();
  Eigen::VectorXd A = Eigen::VectorXd::Zero(n), bA = A, asum = A, bsum = A, bHn = A;
  MatrixX3dR Hn = MatrixX3dR::Zero(n, 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const R3 p[3] = {X.row(T(f, 0)), X.row(T(f, 1)), X.row(T(f, 2))};
    const double af = (p[1] - p[0]).cross(p[2] - p[0]).norm() / 2;
    const double per = (p[1] - p[0]).norm() + (p[2] - p[1]).norm() + (p[0] - p[2]).norm();
    for (int k = 0; k < 3; ++k) {
      const Index a = T(f, k), b = T(f, (k + 1) % 3), c = T(f, (k + 2) % 3);
      const R3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      const double l1 = e1.norm(), l2 = e2.norm();
      const double th = angle(e1, e2), dth = 2 * kR3 * kU * (1 / l1 + 1 / l2);  // angle at a and its bound
      A[a] += af / 3, bA[a] += kR3 * kU * per / 3;
      asum[a] += th, bsum[a] += dth;
      const double s = std::sin(th);
      if (!(s > 0)) {
        bHn[b] = bHn[c] = kInf;  // a degenerate corner: the cotangent is not determined
        continue;
      }
      const double cot = std::cos(th) / s, dcot = dth / (s * s);
      const R3 d = p[(k + 1) % 3] - p[(k + 2) % 3];
      Hn.row(b) += cot * d, Hn.row(c) -= cot * d;
      const double bd = dcot * d.norm() + std::abs(cot) * 2 * kR3 * kU;
      bHn[b] += bd, bHn[c] += bd;
    }
  }
  Curv out;
  out.K.resize(n), out.bK.resize(n), out.R.resize(n), out.bR.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(A[i] > 0)) {
      out.K[i] = out.R[i] = 0, out.bK[i] = out.bR[i] = kInf;
      continue;
    }
    const double K = (2 * M_PI - asum[i]) / A[i], bK = (bsum[i] + std::abs(K) * bA[i]) / A[i];
    const double H = Hn.row(i).norm() / (4 * A[i]), bH = bHn[i] / (4 * A[i]) + H * bA[i] / A[i];
    const double D = std::max(H * H - K, 0.0), bD = 2 * H * bH + bK, s = std::sqrt(D);
    const double bs = D > 0 ? std::min(bD / (2 * s), std::sqrt(bD)) : std::sqrt(bD);
    const double k1 = std::abs(H + s), k2 = std::abs(H - s), mx = std::max(k1, k2), r = mx > 0 ? std::min(k1, k2) / mx : 0;
    out.K[i] = K, out.bK[i] = bK;
    out.R[i] = r, out.bR[i] = mx > 0 ? (bH + bs) * (1 + r) / mx : kInf;
  }
  return out;
}

struct Sph {  // spherical coordinates about the centroid (degrees) with their bounds; per the frame's groups
  Eigen::VectorXd az, el, rho, baz, bel;
  MatrixX3dR d;  // x - centroid
  Eigen::VectorXd rr;
};

// (e, n, u) = (x, y, z) when the third axis is determined; (y, z, x) when the second and third are one group,
// so that the azimuth turns about a determined axis (a rotation within the group only shifts it).
Sph spherical(const MatrixX3dR& X, const VectorXb& used, const FeatureFrame& fr) {
  R3 c = R3::Zero();
  double m = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (used[i]) c += X.row(i), m += 1;
  c /= m;
  const bool rot = fr.group[2] == fr.group[1] && fr.group[1] != fr.group[0];
  const int ie = rot ? 1 : 0, in = rot ? 2 : 1, iu = rot ? 0 : 2;
  Sph s;
  const Eigen::Index n = X.rows();
  s.az.resize(n), s.el.resize(n), s.rho.resize(n), s.baz.resize(n), s.bel.resize(n), s.d.resize(n, 3), s.rr.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const R3 d = X.row(i) - c;
    const double h = std::hypot(d[ie], d[in]);
    s.d.row(i) = d;
    s.az[i] = std::atan2(d[ie], d[in]) * kDeg;
    s.el[i] = std::atan2(d[iu], h) * kDeg;
    s.rho[i] = d.norm();
    s.baz[i] = 2 * std::sqrt(2.0) * kU / h * kDeg;  // x and the centroid each move by <= u
    s.bel[i] = 2 * kR3 * kU / s.rho[i] * kDeg;
  }
  return s;
}
}  // namespace

Eigen::VectorXd lfs76s_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                double dt, double t_max) {
  if (!(dt > 0) || !(t_max >= dt))
    throw MeshError("LFS76 needs dt > 0 and t_max >= dt, got dt=" + std::to_string(dt) + ", t_max=" +
                    std::to_string(t_max));
  const Index n = static_cast<Index>(V.rows());
  const VectorXb used = feature_mesh_check(V, T);
  const FeatureFrame fr = feature_frame(V, used);  // one similarity for both meshes
  const MatrixX3dR& X = fr.X;
  const EdgeList edges = unique_edges(n, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(n, edges.E);
  const int steps = static_cast<int>(std::lround(t_max / dt));
  const MatrixX3dR Xs = laplacian_smooth(X, A, dt, steps);  // heat diffusion, I - D^-1 W, explicit (dt <= 1: convex)
  const MatrixX3dR L = laplacian_coordinates(X, A, 0.0), Ls = laplacian_coordinates(Xs, A, 0.0);
  const double um = dt <= 1 ? kU : kInf;  // the smoothed vertices' noise (a convex combination for dt <= 1)

  std::vector<char> interior(n, 1);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e)
    if (edges.face_count[e] != 2) interior[edges.E(e, 0)] = interior[edges.E(e, 1)] = 0;

  std::vector<NoisyVector> v(19);
  for (auto& x : v) x.reserve(n);
  const R3 c = fr.centroid;
  // vertex normals: normalize(sum of (b - a) x (c - a)); bound 2 sqrt 3 u sum(perimeters) / |sum|
  MatrixX3dR VN = MatrixX3dR::Zero(n, 3), VNs = VN;
  Eigen::VectorXd P = Eigen::VectorXd::Zero(n), Ps = P;
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const R3 a = X.row(T(f, 0)), b = X.row(T(f, 1)), cc = X.row(T(f, 2));
    const R3 as = Xs.row(T(f, 0)), bs = Xs.row(T(f, 1)), cs = Xs.row(T(f, 2));
    const R3 nf = (b - a).cross(cc - a), nfs = (bs - as).cross(cs - as);
    const double pf = (b - a).norm() + (cc - b).norm() + (a - cc).norm(), pfs = (bs - as).norm() + (cs - bs).norm() + (as - cs).norm();
    for (int k = 0; k < 3; ++k) VN.row(T(f, k)) += nf, VNs.row(T(f, k)) += nfs, P[T(f, k)] += pf, Ps[T(f, k)] += pfs;
  }
  for (Index i = 0; i < n; ++i) {
    if (!used[i]) continue;
    const R3 d = X.row(i) - Xs.row(i), dl = L.row(i) - Ls.row(i);
    const R3 pd = pooled_abs(fr, d), pl = pooled_abs(fr, dl);
    const double k = static_cast<double>(A.ptr[i + 1] - A.ptr[i]);
    for (int a = 0; a < 3; ++a) v[a].push(pd[a], kU + um);
    v[3].push(std::abs((X.row(i) - c).norm() - (Xs.row(i) - c).norm()), 2 * kR3 * (kU + um));
    for (int a = 0; a < 3; ++a) v[4 + a].push(pl[a], 2 * k * (kU + um));
    v[7].push(std::abs(L.row(i).norm() - Ls.row(i).norm()), 2 * kR3 * k * (kU + um));
    const double ln = VN.row(i).norm(), lns = VNs.row(i).norm();
    v[10].push(ln > 0 && lns > 0 ? angle(VN.row(i), VNs.row(i)) : 0.0,
               ln > 0 && lns > 0 ? 2 * kR3 * (kU * P[i] / ln + um * Ps[i] / lns) : kInf);
  }
  const MatrixX3dR N = face_normals(X, T), Ns = face_normals(Xs, T);
  const Eigen::VectorXd nu = face_normal_noise(X, T), nus = face_normal_noise(Xs, T);
  for (Eigen::Index f = 0; f < T.rows(); ++f) v[8].push(angle(N.row(f), Ns.row(f)), kU * nu[f] + um * nus[f]);
  const EdgeFaces EF = edge_faces(edges, A, T);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    if (edges.face_count[e] != 2 || EF.f1[e] < 0) continue;
    const Index f0 = EF.f0[e], f1 = EF.f1[e];
    v[9].push(std::abs(angle(N.row(f0), N.row(f1)) - angle(Ns.row(f0), Ns.row(f1))),
              kU * (nu[f0] + nu[f1]) + um * (nus[f0] + nus[f1]));
  }
  const Curv co = curvatures(X, T), cs = curvatures(Xs, T);
  const double sm = um / kU;  // the curvature bounds are per unit noise u
  for (Index i = 0; i < n; ++i)
    if (used[i] && interior[i]) {
      v[11].push(std::abs(co.K[i] - cs.K[i]), co.bK[i] + sm * cs.bK[i]);
      v[12].push(std::abs(co.R[i] - cs.R[i]), co.bR[i] + sm * cs.bR[i]);
    }
  const Sph so = spherical(X, used, fr), ss = spherical(Xs, used, fr);
  const bool full = fr.group[0] == fr.group[2];  // all three axes one group: az / elev undefined, the angle itself
  for (Index i = 0; i < n; ++i)
    if (used[i]) {
      if (full) {
        const double g = angle(so.d.row(i), ss.d.row(i)) * kDeg, bg = so.bel[i] + sm * ss.bel[i];
        v[13].push(g, bg), v[14].push(g, bg);
      } else {
        v[13].push(wrap_deg(so.az[i] - ss.az[i]), so.baz[i] + sm * ss.baz[i]);
        v[14].push(std::abs(so.el[i] - ss.el[i]), so.bel[i] + sm * ss.bel[i]);
      }
      v[15].push(std::abs(so.rho[i] - ss.rho[i]), 2 * kR3 * (kU + um));
    }
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    const Index a = edges.E(e, 0), b = edges.E(e, 1);
    if (full) {
      const double g = std::abs(angle(so.d.row(a), so.d.row(b)) - angle(ss.d.row(a), ss.d.row(b))) * kDeg;
      const double bg = so.bel[a] + so.bel[b] + sm * (ss.bel[a] + ss.bel[b]);
      v[16].push(g, bg), v[17].push(g, bg);
    } else {
      v[16].push(std::abs(wrap_deg(so.az[a] - so.az[b]) - wrap_deg(ss.az[a] - ss.az[b])),
                 so.baz[a] + so.baz[b] + sm * (ss.baz[a] + ss.baz[b]));
      v[17].push(std::abs(std::abs(so.el[a] - so.el[b]) - std::abs(ss.el[a] - ss.el[b])),
                 so.bel[a] + so.bel[b] + sm * (ss.bel[a] + ss.bel[b]));
    }
    v[18].push(std::abs(std::abs(so.rho[a] - so.rho[b]) - std::abs(ss.rho[a] - ss.rho[b])), 4 * kR3 * (kU + um));
  }
  Eigen::VectorXd F = Eigen::VectorXd::Zero(kLfs76sSize);
  for (int j = 0; j < 19; ++j) {
    const double cap = (j >= 13 && j != 15 && j != 18) ? kCapDeg : (j == 11 ? kInf : kCap);
    F.segment<4>(4 * j) = floored_log_moments(v[j], cap);
  }
  return F;
}

}  // namespace meshmark
