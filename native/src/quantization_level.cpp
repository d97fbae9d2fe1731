#include "meshmark/quantization_level.h"
#include "meshmark/error.h"
#include "meshmark/normal_angle_expectation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <string>

namespace meshmark {

namespace {
constexpr int kLowest = -64, kHighest = 160;  // search range of the levels

// per-triangle expectation for noise half-width l
inline double triangle_expectation(const double* h, double l, NoiseBound bound, bool exact, double eta) {
  auto f = [&](double hk) { return exact ? expected_normal_angle(l / hk) : 0.5 * l / hk; };  // eq. 4.1.7 / 4.1.9
  switch (bound) {
    case NoiseBound::Min: return f(h[0]);                           // eq. 4.1.10
    case NoiseBound::Max: return 2 * f(h[0]);                       // eq. 4.1.15
    default: return eta * (f(h[0]) + f(h[1]) + f(h[2]));            // eq. 4.1.16
  }
}

// sum of the linear coefficients: E_lin,j = l * s_j / 2, s_j in 1 / model units
inline double linear_coefficient(const double* h, NoiseBound bound, double eta) {
  switch (bound) {
    case NoiseBound::Min: return 1 / h[0];
    case NoiseBound::Max: return 2 / h[0];
    default: return eta * (1 / h[0] + 1 / h[1] + 1 / h[2]);  // = eta / rho (eq. 4.1.17)
  }
}

inline double half_width(int k, double L) { return std::ldexp(L, -(k + 1)); }  // 2l = 2^-k L (§4.3.1)

void check_positive(double x, const char* name) {
  if (!(x > 0) || !std::isfinite(x))
    throw MeshError(std::string(name) + " must be a finite number > 0, got " + std::to_string(x));
}
}  // namespace

TriangleHeights triangle_heights(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index t = T.rows();
  TriangleHeights H;
  H.h.resize(t, 3);
  H.usable = VectorXb::Zero(t);
  for (Eigen::Index f = 0; f < t; ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    const double area2 = (b - a).cross(c - a).norm();
    double e[3] = {(b - c).norm(), (c - a).norm(), (a - b).norm()};
    std::sort(e, e + 3);  // the longest edge has the smallest height
    const bool ok = area2 > 0 && std::isfinite(area2) && e[0] > 0;
    for (int k = 0; k < 3; ++k) H.h(f, k) = ok ? area2 / e[2 - k] : 0.0;
    H.usable[f] = ok;
    H.n_usable += ok;
  }
  return H;
}

double mesh_normal_expectation(const TriangleHeights& H, double l, NoiseBound bound, bool exact, double eta) {
  if (H.n_usable == 0) return std::numeric_limits<double>::quiet_NaN();
  double s = 0;
  for (Eigen::Index f = 0; f < H.h.rows(); ++f)
    if (H.usable[f]) s += triangle_expectation(&H.h(f, 0), l, bound, exact, eta);
  return s / static_cast<double>(H.n_usable);  // eq. 4.2.18
}

QuantizationLevel quantization_level(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                     double eps, NoiseBound bound, LevelFormula formula, double eta,
                                     double switch_tol) {
  check_positive(eps, "tolerance");
  check_positive(eta, "eta");
  if (!(switch_tol >= 0)) throw MeshError("switch_tol must be >= 0");
  QuantizationLevel out;
  const TriangleHeights H = triangle_heights(V, T);
  if (H.n_usable == 0) throw MeshError("the mesh has no usable triangle (every triangle has zero area)");
  out.n_triangles = H.n_usable;
  out.cube = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  const double L = out.cube, M = static_cast<double>(H.n_usable);
  double S = 0;
  for (Eigen::Index f = 0; f < H.h.rows(); ++f)
    if (H.usable[f]) S += linear_coefficient(&H.h(f, 0), bound, eta);
  S *= L;  // heights in units of L
  // closed form (eqs. 4.3.20, 4.3.21), then the integer boundary checked against E_lin itself
  auto e_lin = [&](int k) { return std::ldexp(S / M, -(k + 2)); };
  const double x = -2 - std::log2(M * eps / S);
  int k = static_cast<int>(std::clamp(std::ceil(x), double(kLowest), double(kHighest)));
  while (k < kHighest && e_lin(k) > eps) ++k;
  while (k > kLowest && e_lin(k - 1) <= eps) --k;
  out.level_linear = k;
  out.e_linear = e_lin(k);
  auto e_ex = [&](int kk) { return mesh_normal_expectation(H, half_width(kk, L), bound, true, eta); };
  out.e_exact = e_ex(k);
  bool exact = formula == LevelFormula::Exact;
  if (formula == LevelFormula::Auto) exact = std::fabs(out.e_linear - out.e_exact) > switch_tol * out.e_exact;
  out.used_exact = exact;
  if (exact) {  // E_mesh decreases with k: walk from the closed-form level to the boundary
    double e = out.e_exact;
    while (k < kHighest && e > eps) e = e_ex(++k);
    while (k > kLowest) {
      const double e1 = e_ex(k - 1);
      if (e1 > eps) break;
      --k;
      e = e1;
    }
    out.e_level = e;
  } else {
    out.e_level = out.e_linear;
  }
  out.level_unclamped = k;
  out.level = std::clamp(k, 0, 32);
  return out;
}

AdaptiveLevels adaptive_levels(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                               const Eigen::Ref<const Eigen::VectorXd>& kappa, double eps0, double alpha, double mu,
                               double sigma, double eta) {
  check_positive(eps0, "tolerance");
  check_positive(sigma, "sigma");
  check_positive(eta, "eta");
  if (!std::isfinite(alpha) || !std::isfinite(mu)) throw MeshError("alpha and mu must be finite");
  if (kappa.size() != V.rows()) throw MeshError("adaptive_levels: kappa needs one value per vertex");
  const TriangleHeights H = triangle_heights(V, T);
  if (H.n_usable == 0) throw MeshError("the mesh has no usable triangle (every triangle has zero area)");
  const double L = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  const Eigen::Index t = T.rows(), n = V.rows();
  AdaptiveLevels out;
  out.triangle_level = VectorXi::Constant(t, INT32_MIN);
  out.triangle_tolerance = Eigen::VectorXd::Constant(t, std::numeric_limits<double>::quiet_NaN());
  out.vertex_level = VectorXi::Constant(n, INT32_MIN);
  VectorXb touched = VectorXb::Zero(n);
  for (Eigen::Index f = 0; f < t; ++f) {
    for (int c = 0; c < 3; ++c) touched[T(f, c)] = 1;
    if (!H.usable[f]) continue;
    double ej = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; ++c) {  // eq. 4.3.24
      const double d = kappa[T(f, c)] - mu;
      ej = std::min(ej, alpha - alpha * std::exp(-d * d / (2 * sigma * sigma)) + eps0);
    }
    out.triangle_tolerance[f] = ej;
    const double* h = &H.h(f, 0);
    if (!(ej > 0)) {
      out.triangle_level[f] = kHighest;
    } else {
      const double s = L * linear_coefficient(h, NoiseBound::Appr, eta);
      int k = static_cast<int>(std::clamp(std::ceil(-2 - std::log2(ej / s)), double(kLowest), double(kHighest)));
      auto e = [&](int kk) { return triangle_expectation(h, half_width(kk, L), NoiseBound::Appr, true, eta); };
      while (k < kHighest && e(k) > ej) ++k;  // eq. 4.3.25 with the exact E(theta)
      while (k > kLowest && e(k - 1) <= ej) --k;
      out.triangle_level[f] = k;
    }
    for (int c = 0; c < 3; ++c) {
      Index& vl = out.vertex_level[T(f, c)];
      vl = std::max(vl, out.triangle_level[f]);
    }
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    if (!touched[v]) out.vertex_level[v] = 0;                       // unreferenced: no normal depends on it
    else if (out.vertex_level[v] == INT32_MIN) out.vertex_level[v] = 32;  // only degenerate triangles: keep all
    else out.vertex_level[v] = std::clamp(out.vertex_level[v], 0, 32);
  }
  return out;
}

}  // namespace meshmark
