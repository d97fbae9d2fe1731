#include "meshmark/quantization_level.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"
#include "meshmark/normal_angle_expectation.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace meshmark {

namespace {
constexpr int kLowest = -64, kHighest = 160;  // search range of the levels

// per-triangle expectation for noise half-width l
inline double triangle_expectation(const double* q, double l, NoiseBound bound, bool exact, double eta) {
  // q = inverse heights, r = l / h = l q
  auto f = [&](double qk) {  // eq. 4.1.7 / 4.1.9 (the series inline: the same value as the call)
    const double r = l * qk;
    return exact ? (r >= 0 && r < 0.05 ? expected_normal_angle_series(r) : expected_normal_angle(r)) : 0.5 * l * qk;
  };
  switch (bound) {
    case NoiseBound::Min: return f(q[0]);                           // eq. 4.1.10
    case NoiseBound::Max: return 2 * f(q[0]);                       // eq. 4.1.15
    default: return eta * (f(q[0]) + f(q[1]) + f(q[2]));            // eq. 4.1.16
  }
}

// sum of the linear coefficients: E_lin,j = l * s_j / 2, s_j in 1 / model units
inline double linear_coefficient(const double* q, NoiseBound bound, double eta) {
  switch (bound) {
    case NoiseBound::Min: return q[0];
    case NoiseBound::Max: return 2 * q[0];
    default: return eta * (q[0] + q[1] + q[2]);  // = eta / rho (eq. 4.1.17)
  }
}

// closed form (eqs. 4.3.20, 4.3.21) for S = L sum_j s_j, then the integer boundary checked against E_lin itself
inline double e_lin(double S, double M, int k) { return std::ldexp(S / M, -(k + 2)); }
inline int linear_level(double S, double M, double eps) {
  const double x = -2 - std::log2(M * eps / S);
  int k = static_cast<int>(std::clamp(std::ceil(x), double(kLowest), double(kHighest)));
  while (k < kHighest && e_lin(S, M, k) > eps) ++k;
  while (k > kLowest && e_lin(S, M, k - 1) <= eps) --k;
  return k;
}

inline double half_width(int k, double L) { return std::ldexp(L, -(k + 1)); }  // 2l = 2^-k L (§4.3.1)

void check_positive(double x, const char* name) {
  if (!(x > 0) || !std::isfinite(x))
    throw MeshError(std::string(name) + " must be a finite number > 0, got " + std::to_string(x));
}
}  // namespace

namespace {
// eq. 4.3.25 for one triangle (inverse heights h): the smallest k with E_appr,j(k) <= ej, exact E(theta),
// searched from the closed form (kHighest if ej <= 0).
inline int triangle_level(const double* h, double ej, double L, double eta) {
  if (!(ej > 0)) return kHighest;
  const double s = L * linear_coefficient(h, NoiseBound::Appr, eta);
  int k = static_cast<int>(std::clamp(std::ceil(-2 - std::log2(ej / s)), double(kLowest), double(kHighest)));
  auto e = [&](int kk) { return triangle_expectation(h, half_width(kk, L), NoiseBound::Appr, true, eta); };
  // while (k < kHighest && e(k) > ej) ++k; while (k > kLowest && e(k - 1) <= ej) --k; without
  // evaluating e twice at one k, nor where the outcome is known: after a step up, e(k - 1) > ej was
  // just seen; and where every l/h of level k - 1 is in the series branch, the computed e(k - 1) is
  // >= the computed tangent form eta (r1/2 + r2/2 + r3/2) (expected_normal_angle_series, and rounding
  // is monotone), so a tangent form > ej decides without the series.
  bool up = false;
  while (k < kHighest && e(k) > ej) ++k, up = true;
  if (up) return k;
  while (k > kLowest) {
    const double l = half_width(k - 1, L);
    if (l * h[0] < 0.05 && eta * (0.5 * (l * h[0]) + 0.5 * (l * h[1]) + 0.5 * (l * h[2])) > ej) break;
    if (!(e(k - 1) <= ej)) break;
    --k;
  }
  return k;
}

// Calls fn(f, q, ok) for every triangle with q[3] its inverse heights 1/h1 >= 1/h2 >= 1/h3
// (|edge| / 2 area; 0 if not ok = zero or non-finite area). Raw pointers: this loop is the cost of a
// level on a large mesh (three vertex gathers per triangle).
template <class Fn>
void for_each_inverse_heights(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T, Fn&& fn) {
  const double* vp = V.data();
  const Eigen::Index vs = V.outerStride();
  constexpr Eigen::Index kAhead = 16;  // software prefetch of the corners a few triangles ahead
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    if (f + kAhead < T.rows())
      for (int c = 0; c < 3; ++c) __builtin_prefetch(vp + vs * T(f + kAhead, c));
    const double* a = vp + vs * T(f, 0);
    const double* b = vp + vs * T(f, 1);
    const double* c = vp + vs * T(f, 2);
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double bc[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]};
    const double cx = ab[1] * ac[2] - ab[2] * ac[1], cy = ab[2] * ac[0] - ab[0] * ac[2],
                 cz = ab[0] * ac[1] - ab[1] * ac[0];
    const double area2 = std::sqrt(cx * cx + cy * cy + cz * cz);
    const double e0 = std::sqrt(bc[0] * bc[0] + bc[1] * bc[1] + bc[2] * bc[2]);
    const double e1 = std::sqrt(ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2]);
    const double e2 = std::sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
    const double lo = std::min(e0, std::min(e1, e2)), hi = std::max(e0, std::max(e1, e2));
    const double mid = e0 + e1 + e2 - lo - hi;
    const bool ok = area2 > 0 && std::isfinite(area2) && lo > 0;
    // 1 / h_k = |opposite edge| / 2 area: the longest edge has the smallest height
    const double inv = ok ? 1.0 / area2 : 0.0;
    const double q[3] = {hi * inv, mid * inv, lo * inv};
    fn(f, q, ok);
  }
}

// T's rows grouped by the block of 2^5 vertices their first corner lies in (a counting sort, stable),
// for order-free per-triangle work: the vertex gathers of consecutive triangles then stay in cache.
// A face order that jumps over the vertex array (the bench's subdivided mesh: mean jump 43k vertices)
// otherwise makes the gathers ~3x the cost of the arithmetic.
MatrixX3iR rows_by_vertex_block(const Eigen::Ref<const MatrixX3iR>& T, Eigen::Index n) {
  constexpr int kShift = 5;
  std::vector<Eigen::Index> start(static_cast<std::size_t>((n >> kShift) + 2), 0);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      if (T(f, c) < 0 || T(f, c) >= n) throw MeshError("triangle " + std::to_string(f) + " has a vertex out of range");
    ++start[static_cast<std::size_t>(T(f, 0) >> kShift) + 1];
  }
  for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  MatrixX3iR out(T.rows(), 3);
  advise_huge_pages(out.data(), static_cast<std::size_t>(T.rows()) * 3 * sizeof(Index));
  for (Eigen::Index f = 0; f < T.rows(); ++f) out.row(start[static_cast<std::size_t>(T(f, 0) >> kShift)]++) = T.row(f);
  return out;
}
}  // namespace

TriangleHeights triangle_heights(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  TriangleHeights H;
  H.inv_h.resize(T.rows(), 3);
  H.usable = VectorXb::Zero(T.rows());
  for_each_inverse_heights(V, T, [&](Eigen::Index f, const double* q, bool ok) {
    for (int k = 0; k < 3; ++k) H.inv_h(f, k) = q[k];
    H.usable[f] = ok;
    H.n_usable += ok;
  });
  return H;
}

double mesh_normal_expectation(const TriangleHeights& H, double l, NoiseBound bound, bool exact, double eta) {
  if (H.n_usable == 0) return std::numeric_limits<double>::quiet_NaN();
  double s = 0;
  for (Eigen::Index f = 0; f < H.inv_h.rows(); ++f)
    if (H.usable[f]) s += triangle_expectation(&H.inv_h(f, 0), l, bound, exact, eta);
  return s / static_cast<double>(H.n_usable);  // eq. 4.2.18
}

QuantizationLevel quantization_level(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                     double eps, NoiseBound bound, LevelFormula formula, double eta,
                                     double switch_tol) {
  check_positive(eps, "tolerance");
  check_positive(eta, "eta");
  if (!(switch_tol >= 0)) throw MeshError("switch_tol must be >= 0");
  QuantizationLevel out;
  // one pass over the geometry; the exact checks then read the stored inverse heights (measured: the
  // gathers and square roots cost ~3x more than writing and re-reading (t,3) doubles)
  const TriangleHeights H = triangle_heights(V, T);
  if (H.n_usable == 0) throw MeshError("the mesh has no usable triangle (every triangle has zero area)");
  out.n_triangles = H.n_usable;
  out.cube = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  const double L = out.cube, M = static_cast<double>(H.n_usable);
  double S = 0;
  for (Eigen::Index f = 0; f < H.inv_h.rows(); ++f)
    if (H.usable[f]) S += linear_coefficient(&H.inv_h(f, 0), bound, eta);
  S *= L;  // heights in units of L
  int k = linear_level(S, M, eps);
  out.level_linear = k;
  out.e_linear = e_lin(S, M, k);
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
    out.triangle_level[f] = triangle_level(&H.inv_h(f, 0), ej, L, eta);
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

std::optional<int> quantization_level_only(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                           double eps, NoiseBound bound, LevelFormula formula, double eta,
                                           double switch_tol) {
  check_positive(eps, "tolerance");
  check_positive(eta, "eta");
  if (!(switch_tol >= 0)) throw MeshError("switch_tol must be >= 0");
  // quantization_level with the triangles in vertex-block order (sums in another order)
  const MatrixX3iR Tb = rows_by_vertex_block(T, V.rows());
  const TriangleHeights H = triangle_heights(V, Tb);
  if (H.n_usable == 0) throw MeshError("the mesh has no usable triangle (every triangle has zero area)");
  const double L = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff(), M = static_cast<double>(H.n_usable);
  double S = 0;
  for (Eigen::Index f = 0; f < H.inv_h.rows(); ++f)
    if (H.usable[f]) S += linear_coefficient(&H.inv_h(f, 0), bound, eta);
  S *= L;
  // Sums of M non-negative terms in any order are within gamma_M = M u / (1 - M u) of the exact sum;
  // with the division and the scaling, a value here and the same value of quantization_level differ
  // by less than d relative. A comparison with eps (or switch_tol) further than that from equality
  // has the same outcome there; closer ones are left to quantization_level.
  const double u = std::numeric_limits<double>::epsilon() / 2, d = 3 * M * u + 8 * u;
  if (!(d < 1e-6) || !(eps > 1e-250)) return std::nullopt;  // (and nothing near underflow)
  auto clear = [&](double e, double thr) { return std::fabs(e - thr) > 2 * d * std::max(std::fabs(e), std::fabs(thr)); };
  int k = linear_level(S, M, eps);  // the smallest k in range with E_lin(k) <= eps
  if ((k < kHighest && !clear(e_lin(S, M, k), eps)) || (k > kLowest && !clear(e_lin(S, M, k - 1), eps)))
    return std::nullopt;
  bool exact = formula == LevelFormula::Exact;
  auto e_ex = [&](int kk) { return mesh_normal_expectation(H, half_width(kk, L), bound, true, eta); };
  if (formula == LevelFormula::Auto) {
    const double el = e_lin(S, M, k), ex = e_ex(k);
    const double gap = std::fabs(el - ex) - switch_tol * ex;  // used_exact iff gap > 0
    if (!(std::fabs(gap) > 4 * d * (el + ex) * (1 + switch_tol))) return std::nullopt;
    exact = gap > 0;
  }
  if (exact) {  // the walk of quantization_level, every comparison with a margin
    double e = e_ex(k);
    while (k < kHighest) {
      if (!clear(e, eps)) return std::nullopt;
      if (!(e > eps)) break;
      e = e_ex(++k);
    }
    while (k > kLowest) {
      const double e1 = e_ex(k - 1);
      if (!clear(e1, eps)) return std::nullopt;
      if (e1 > eps) break;
      --k;
    }
  }
  return std::clamp(k, 0, 32);
}

std::optional<VectorXi> uniform_adaptive_levels(const Eigen::Ref<const MatrixX3dR>& V,
                                                const Eigen::Ref<const MatrixX3iR>& T, double eps0, double eta) {
  check_positive(eps0, "tolerance");
  check_positive(eta, "eta");
  const double* vp = V.data();
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int a = 0; a < 3; ++a)
      if (!(std::fabs(vp[V.outerStride() * i + a]) < 0x1p400)) return std::nullopt;  // kappa could be NaN
  const double L = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  // One pass: INT32_MIN = no triangle, INT32_MIN + 1 = only unusable triangles, else the largest level
  constexpr int kNone = INT32_MIN, kUnusable = INT32_MIN + 1;
  VectorXi level = VectorXi::Constant(V.rows(), kNone);
  Eigen::Index n_usable = 0;
  // a vertex's level is a max over its triangles: any triangle order gives the same result
  const MatrixX3iR Tb = rows_by_vertex_block(T, V.rows());
  for_each_inverse_heights(V, Tb, [&](Eigen::Index f, const double* q, bool ok) {
    n_usable += ok;
    if (f + 16 < Tb.rows())
      for (int c = 0; c < 3; ++c) __builtin_prefetch(level.data() + Tb(f + 16, c), 1);
    const int k = ok ? triangle_level(q, eps0, L, eta) : kUnusable;  // eps_j = eps0 (eq. 4.3.24, alpha = 0)
    for (int c = 0; c < 3; ++c) {
      Index& vl = level[Tb(f, c)];
      vl = std::max(vl, k);
    }
  });
  if (n_usable == 0) throw MeshError("the mesh has no usable triangle (every triangle has zero area)");
  for (Eigen::Index v = 0; v < level.size(); ++v)
    level[v] = level[v] == kNone ? 0 : level[v] == kUnusable ? 32 : std::clamp(level[v], 0, 32);
  return level;
}

}  // namespace meshmark
