// meshmark: the expected normal change of a triangle under uniform cubic noise (thesis §4.1).
#pragma once
#include "meshmark/mesh.h"

#include <cstdint>

namespace meshmark {

// E(theta) of eq. 4.1.7 (plus eq. 4.1.8 when r > 1): the expected angle, radians, between the normal
// of a triangle and its normal after uniform noise with cubic support of edge length 2l (one face
// parallel to the triangle) is added to one vertex whose height is h; r = l / h >= 0.
// Evaluated as the closed form for 0.05 <= r <= 1e3 (log|1 - r| and the principal arctan; the
// r = 1 limit is taken), by its Taylor series r/2 + r^3/12 - r^5/30 - 5 r^7/168 + r^9/30 +
// 5 r^11/132 below 0.05 (the closed form cancels there), and by pi/2 - (ln 4 + pi)/(4r) +
// 1/(12 r^3) above 1e3; r = +inf gives pi/2. E'(0) = 1/2 (eq. 4.1.9). MeshError if r < 0 or NaN.
double expected_normal_angle(double r);

// The branch r < 0.05 of expected_normal_angle (its Taylor series at 0), inline for the per-triangle
// level searches; expected_normal_angle(r) == expected_normal_angle_series(r) for 0 <= r < 0.05.
// Every coefficient after 1/12 makes the bracket smaller, so for such r the computed value is
// >= r/2 (the tangent, eq. 4.1.9) exactly: quantization_level.cpp relies on that.
inline double expected_normal_angle_series(double r) {
  const double r2 = r * r;  // next term -127 r^13 / 2730 (derived with sympy)
  return r * (0.5 + r2 * (1.0 / 12 + r2 * (-1.0 / 30 + r2 * (-5.0 / 168 + r2 * (1.0 / 30 + r2 * (5.0 / 132))))));
}

struct MonteCarloAngle {
  double mean = 0;     // mean angle, radians
  double stderr_ = 0;  // standard error of the mean
  std::int64_t n = 0;
};

// Monte Carlo of the same expectation for any triangle P (3 rows) and any subset of its vertices:
// every vertex k with noisy[k] gets u_k ~ U[-l, l]^3 (axes of the coordinate system), and the angle
// atan2(|n x n'|, n . n') in [0, pi] between the normals of P and of the noisy triangle is averaged
// over n samples drawn with Rng(seed) (for each sample, vertex by vertex, x, y, z). Samples whose
// noisy triangle is degenerate (zero normal) count as pi/2. MeshError if l < 0, n < 1 or P is
// degenerate.
MonteCarloAngle normal_noise_monte_carlo(const Eigen::Matrix3d& P, const Eigen::Vector3i& noisy, double l,
                                         std::int64_t n, std::uint64_t seed);

}  // namespace meshmark
