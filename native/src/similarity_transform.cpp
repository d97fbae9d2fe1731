#include "meshmark/similarity_transform.h"
#include "meshmark/error.h"

#include <cmath>

namespace meshmark {

MatrixX3dR similarity_transform(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Matrix3d& R, double s,
                                const Eigen::Vector3d& t) {
  if (!std::isfinite(s) || !R.allFinite() || !t.allFinite())
    throw MeshError("similarity transform: rotation, scale and translation must be finite");
  const Eigen::Matrix3d M = s * R;
  MatrixX3dR out(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d v = V.row(i).transpose();
    out.row(i) = (M * v + t).transpose();
  }
  return out;
}

Eigen::Matrix3d axis_angle_rotation(const Eigen::Vector3d& axis, double angle_deg) {
  const double len = axis.norm();
  if (!(len > 0) || !std::isfinite(len) || !std::isfinite(angle_deg))
    throw MeshError("rotation axis must be a finite non-zero vector and the angle finite");
  const Eigen::Vector3d a = axis / len;
  const double th = angle_deg * M_PI / 180.0, c = std::cos(th), s = std::sin(th), C = 1 - c;
  const double x = a[0], y = a[1], z = a[2];
  Eigen::Matrix3d R;  // Rodrigues' formula
  R << x * x * C + c, x * y * C - z * s, x * z * C + y * s,
       x * y * C + z * s, y * y * C + c, y * z * C - x * s,
       x * z * C - y * s, y * z * C + x * s, z * z * C + c;
  return R;
}

Eigen::Matrix3d random_rotation(Rng& rng) {
  const double u0 = rng.uniform01(), u1 = rng.uniform01(), u2 = rng.uniform01();
  const double a = std::sqrt(1 - u0), b = std::sqrt(u0);
  const double x = a * std::sin(2 * M_PI * u1), y = a * std::cos(2 * M_PI * u1);
  const double z = b * std::sin(2 * M_PI * u2), w = b * std::cos(2 * M_PI * u2);
  Eigen::Matrix3d R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
       2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
       2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y);
  return R;
}

}  // namespace meshmark
