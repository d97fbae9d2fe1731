#include "meshmark/curvature_degradation.h"
#include "meshmark/error.h"
#include "meshmark/normal_degradation_sweep.h"
#include "meshmark/rng.h"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

namespace meshmark {

namespace {
// angle_sum with two atan2 per triangle (the third angle is pi minus the others): the sweep spends
// its time here. Same convention as interior_angles (a zero-length side gives 0 at its corners).
void fast_angle_sum(const MatrixX3dR& V, const Eigen::Ref<const MatrixX3iR>& T, Eigen::VectorXd& S) {
  S.setZero(V.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Index i = T(f, 0), j = T(f, 1), k = T(f, 2);
    const Eigen::Vector3d a = V.row(i), b = V.row(j), c = V.row(k);
    const Eigen::Vector3d ab = b - a, ac = c - a, bc = c - b;
    const double cr = ab.cross(ac).norm();  // |ab x ac| = |ba x bc|, twice the area
    if (ab.squaredNorm() == 0 || ac.squaredNorm() == 0 || bc.squaredNorm() == 0) {
      const auto one = [](const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
        return u.squaredNorm() == 0 || v.squaredNorm() == 0 ? 0.0 : std::atan2(u.cross(v).norm(), u.dot(v));
      };
      S[i] += one(ab, ac);
      S[j] += one(-ab, bc);
      S[k] += one(-ac, -bc);
      continue;
    }
    const double A = std::atan2(cr, ab.dot(ac)), B = std::atan2(cr, -ab.dot(bc));
    S[i] += A;
    S[j] += B;
    S[k] += M_PI - A - B;
  }
}
}  // namespace

MatrixX3dR mean_face_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  MatrixX3dR N = MatrixX3dR::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0) || !std::isfinite(len)) continue;
    n /= len;
    for (int k = 0; k < 3; ++k) N.row(T(f, k)) += n.transpose();
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

Eigen::VectorXd curvature_degradation(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                      const Eigen::Ref<const VectorXi>& t, Displacement direction,
                                      const Eigen::Ref<const VectorXb>& moved, const Eigen::Ref<const VectorXb>& measured,
                                      double scale, int repeats, std::uint64_t seed) {
  const Eigen::Index n = V.rows();
  if (repeats < 1) throw MeshError("repeats must be >= 1, got " + std::to_string(repeats));
  if (!(scale > 0) || !std::isfinite(scale)) throw MeshError("scale must be a finite number > 0");
  if (moved.size() != n || measured.size() != n) throw MeshError("the vertex masks need one entry per vertex");
  for (Eigen::Index j = 0; j < t.size(); ++j)
    if (t[j] < 0 || t[j] > 1074) throw MeshError("level t = " + std::to_string(t[j]) + " is outside 0..1074");
  Eigen::Index n_measured = 0;
  for (Eigen::Index v = 0; v < n; ++v) n_measured += measured[v] != 0;
  if (n_measured == 0) throw MeshError("no vertex to measure (no interior vertex)");
  const MatrixX3dR N = mean_face_normals(V, T);
  // an orthonormal tangent basis per vertex (e1 from the coordinate axis least aligned with n)
  MatrixX3dR E1 = MatrixX3dR::Zero(n, 3), E2 = MatrixX3dR::Zero(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d nv = N.row(v);
    if (nv.squaredNorm() == 0) continue;
    Eigen::Index axis;
    nv.cwiseAbs().minCoeff(&axis);
    const Eigen::Vector3d e1 = nv.cross(Eigen::Vector3d::Unit(axis)).normalized();
    E1.row(v) = e1.transpose();
    E2.row(v) = nv.cross(e1).transpose();
  }
  Eigen::VectorXd S0;
  fast_angle_sum(MatrixX3dR(V), T, S0);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(t.size());
  MatrixX3dR V2(n, 3);
  Eigen::VectorXd S;
  for (Eigen::Index j = 0; j < t.size(); ++j) {
    const double amp = scale * std::ldexp(1.0, 1 - t[j]);
    double acc = 0;
    for (int r = 0; r < repeats; ++r) {
      Rng rng(sweep_seed(seed, t[j], r));
      V2 = V;
      for (Eigen::Index v = 0; v < n; ++v) {
        if (!moved[v]) continue;
        const double s = rng.uniform(-amp, amp);
        Eigen::Vector3d u;
        if (direction == Displacement::Normal) {
          u = N.row(v).transpose();
        } else if (direction == Displacement::Tangential) {
          const double phi = rng.uniform(0.0, 2 * M_PI);
          u = std::cos(phi) * E1.row(v).transpose() + std::sin(phi) * E2.row(v).transpose();
        } else {
          u = Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
          u /= u.norm();
        }
        V2.row(v) += s * u.transpose();
      }
      fast_angle_sum(V2, T, S);
      double sum = 0;
      for (Eigen::Index v = 0; v < n; ++v)
        if (measured[v]) sum += std::fabs(S[v] - S0[v]);  // |kappa' - kappa|, eq. 5.1.1
      acc += sum / static_cast<double>(n_measured);
    }
    out[j] = acc / repeats;
  }
  return out;
}

}  // namespace meshmark
