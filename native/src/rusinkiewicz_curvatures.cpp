#include "meshmark/rusinkiewicz_curvatures.h"

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <cmath>
#include <vector>

namespace meshmark {

namespace {
using R3 = Eigen::RowVector3d;
R3 normr(const R3& v) { return v / v.norm(); }

// RotateCoordinateSystem: the frame (up, vp) rotated into the plane with normal nf.
void rotate_frame(const R3& up, const R3& vp, const R3& nf, R3& ru, R3& rv) {
  ru = up, rv = vp;
  const R3 np = normr(up.cross(vp));
  const double ndot = nf.dot(np);
  if (ndot <= -1) {
    ru = -ru, rv = -rv;
    return;
  }
  const R3 perp = nf - ndot * np, dperp = (np + nf) / (1 + ndot);
  ru = ru - dperp * perp.dot(ru);
  rv = rv - dperp * perp.dot(rv);
}
}  // namespace

PrincipalCurvatures rusinkiewicz_curvatures(const Eigen::Ref<const MatrixX3dR>& X, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index n = X.rows(), nf = T.rows();
  MatrixX3dR FN(nf, 3), VN = MatrixX3dR::Zero(n, 3), up = MatrixX3dR::Zero(n, 3), vp(n, 3);
  MatrixX3dR e0(nf, 3), e1(nf, 3), e2(nf, 3), Acorner(nf, 3);
  Eigen::VectorXd Avertex = Eigen::VectorXd::Zero(n);
  for (Eigen::Index f = 0; f < nf; ++f) {  // CalcFaceNormals, CalcVertexNormals
    const R3 v0 = X.row(T(f, 0)), v1 = X.row(T(f, 1)), v2 = X.row(T(f, 2));
    e0.row(f) = v2 - v1, e1.row(f) = v0 - v2, e2.row(f) = v1 - v0;
    FN.row(f) = normr(R3(e0.row(f)).cross(R3(e1.row(f))));
    const double de0 = e0.row(f).norm(), de1 = e1.row(f).norm(), de2 = e2.row(f).norm();
    const double l0 = de0 * de0, l1 = de1 * de1, l2 = de2 * de2;
    const double ew0 = l0 * (l1 + l2 - l0), ew1 = l1 * (l2 + l0 - l1), ew2 = l2 * (l0 + l1 - l2);
    const double s = (de0 + de1 + de2) / 2, heron = s * (s - de0) * (s - de1) * (s - de2);
    const double Af = heron > 0 ? std::sqrt(heron) : 0.0;  // MATLAB: sqrt of a negative is imaginary, real() drops it
    VN.row(T(f, 0)) += Af / (l1 * l2) * FN.row(f);
    VN.row(T(f, 1)) += Af / (l0 * l2) * FN.row(f);
    VN.row(T(f, 2)) += Af / (l1 * l0) * FN.row(f);
    double a0, a1, a2;
    if (ew0 <= 0) {
      a1 = -0.25 * l2 * Af / e0.row(f).dot(e2.row(f));
      a2 = -0.25 * l1 * Af / e0.row(f).dot(e1.row(f));
      a0 = Af - a1 - a2;
    } else if (ew1 <= 0) {
      a2 = -0.25 * l0 * Af / e1.row(f).dot(e0.row(f));
      a0 = -0.25 * l2 * Af / e1.row(f).dot(e2.row(f));
      a1 = Af - a0 - a2;
    } else if (ew2 <= 0) {
      a0 = -0.25 * l1 * Af / e2.row(f).dot(e1.row(f));
      a1 = -0.25 * l0 * Af / e2.row(f).dot(e0.row(f));
      a2 = Af - a0 - a1;
    } else {
      const double ews = 0.5 * Af / (ew0 + ew1 + ew2);
      a0 = ews * (ew1 + ew2), a1 = ews * (ew0 + ew2), a2 = ews * (ew1 + ew0);
    }
    Acorner.row(f) << a0, a1, a2;
    Avertex[T(f, 0)] += a0, Avertex[T(f, 1)] += a1, Avertex[T(f, 2)] += a2;
    up.row(T(f, 0)) = normr(e2.row(f)), up.row(T(f, 1)) = normr(e0.row(f)), up.row(T(f, 2)) = normr(e1.row(f));
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    VN.row(i) = normr(VN.row(i));
    const R3 u = normr(R3(up.row(i)).cross(R3(VN.row(i))));
    up.row(i) = u;
    vp.row(i) = R3(VN.row(i)).cross(u);
  }
  std::vector<Eigen::Vector3d> sfm(n, Eigen::Vector3d::Zero());  // VertexSFM: (ku, kuv, kv)
  Eigen::Matrix<double, 6, 3> A;
  Eigen::Matrix<double, 6, 1> b;
  for (Eigen::Index f = 0; f < nf; ++f) {  // CalcCurvature
    const R3 nrm = FN.row(f), t = normr(e0.row(f)), B = normr(nrm.cross(t));
    const R3 n0 = VN.row(T(f, 0)), n1 = VN.row(T(f, 1)), n2 = VN.row(T(f, 2));
    const R3 E[3] = {e0.row(f), e1.row(f), e2.row(f)}, D[3] = {n2 - n1, n0 - n2, n1 - n0};
    for (int k = 0; k < 3; ++k) {
      A.row(2 * k) << E[k].dot(t), E[k].dot(B), 0;
      A.row(2 * k + 1) << 0, E[k].dot(t), E[k].dot(B);
      b[2 * k] = D[k].dot(t), b[2 * k + 1] = D[k].dot(B);
    }
    const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);  // x = A \ b
    Eigen::Matrix2d old;
    old << x[0], x[1], x[1], x[2];
    for (int j = 0; j < 3; ++j) {  // ProjectCurvatureTensor into the vertex frame
      const Index v = T(f, j);
      const double w = Acorner(f, j) / Avertex[v];
      R3 ru, rv;
      rotate_frame(up.row(v), vp.row(v), nrm, ru, rv);
      const Eigen::RowVector2d p(ru.dot(t), ru.dot(B)), q(rv.dot(t), rv.dot(B));
      sfm[v] += w * Eigen::Vector3d(p * old * p.transpose(), p * old * q.transpose(), q * old * q.transpose());
    }
  }
  PrincipalCurvatures out;
  out.k1.resize(n), out.k2.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {  // getPrincipalCurvatures: one Jacobi rotation
    const double ku = sfm[i][0], kuv = sfm[i][1], kv = sfm[i][2];
    double tt = 0;
    if (kuv != 0) {
      const double h = 0.5 * (kv - ku) / kuv;
      tt = h < 0 ? 1 / (h - std::sqrt(1 + h * h)) : 1 / (h + std::sqrt(1 + h * h));
    }
    double k1 = ku - tt * kuv, k2 = kv + tt * kuv;
    if (!(std::abs(k1) >= std::abs(k2))) std::swap(k1, k2);
    out.k1[i] = k1, out.k2[i] = k2;  // a vertex in no face: 0, 0 (its ratio 0 / 0 is NaN)
  }
  return out;
}

}  // namespace meshmark
