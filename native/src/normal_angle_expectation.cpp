#include "meshmark/normal_angle_expectation.h"
#include "meshmark/error.h"
#include "meshmark/rng.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>

namespace meshmark {

double expected_normal_angle(double r) {
  if (!(r >= 0)) throw MeshError("expected_normal_angle: r = l/h must be >= 0, got " + std::to_string(r));
  if (std::isinf(r)) return M_PI / 2;
  if (r < 0.05) return expected_normal_angle_series(r);  // Taylor series of eq. 4.1.7 at 0
  if (r > 1e3) {  // expansion at infinity of eq. 4.1.7 + 4.1.8
    const double x = 1 / r;
    return M_PI / 2 - (std::log(4.0) + M_PI) / 4 * x + x * x * x / 12;
  }
  // eq. 4.1.7 with the log of the quotient expanded into a sum (|1 - r| for r > 1)
  const double a = 1 - r, b = 1 + r;
  const double L = (1 - 2 * r) * std::log(a * a + r * r) + 2 * b * b * std::log(b) -
                   (1 + 2 * r) * std::log(b * b + r * r) - (r == 1 ? 0.0 : 2 * a * a * std::log(std::fabs(a)));
  double E = L / (8 * r * r) + b / (2 * r) * std::atan(r / b) - (r == 1 ? 0.0 : a / (2 * r) * std::atan(r / a));
  if (r > 1) E += M_PI * (r - 1) / (2 * r);  // eq. 4.1.8
  return E;
}

MonteCarloAngle normal_noise_monte_carlo(const Eigen::Matrix3d& P, const Eigen::Vector3i& noisy, double l,
                                         std::int64_t n, std::uint64_t seed) {
  if (!(l >= 0) || !std::isfinite(l)) throw MeshError("normal_noise_monte_carlo: l must be finite and >= 0");
  if (n < 1) throw MeshError("normal_noise_monte_carlo: n must be >= 1");
  const Eigen::Vector3d a = P.row(0), b = P.row(1), c = P.row(2);
  const Eigen::Vector3d n0 = (b - a).cross(c - a);
  if (!(n0.norm() > 0)) throw MeshError("normal_noise_monte_carlo: the triangle is degenerate");
  Rng rng(seed);
  double s = 0, s2 = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    Eigen::Vector3d q[3] = {a, b, c};
    for (int k = 0; k < 3; ++k)
      if (noisy[k])
        for (int d = 0; d < 3; ++d) q[k][d] += rng.uniform(-l, l);
    const Eigen::Vector3d n1 = (q[1] - q[0]).cross(q[2] - q[0]);
    const double th = n1.squaredNorm() > 0 ? std::atan2(n0.cross(n1).norm(), n0.dot(n1)) : M_PI / 2;
    s += th;
    s2 += th * th;
  }
  MonteCarloAngle out;
  out.n = n;
  out.mean = s / static_cast<double>(n);
  const double var = n > 1 ? (s2 - s * out.mean) / static_cast<double>(n - 1) : 0.0;
  out.stderr_ = std::sqrt(std::max(var, 0.0) / static_cast<double>(n));
  return out;
}

}  // namespace meshmark
