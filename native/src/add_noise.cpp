#include "meshmark/add_noise.h"
#include "meshmark/error.h"
#include "meshmark/mean_centroid_distance.h"
#include "meshmark/rng.h"
#include "meshmark/vertex_normals.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace meshmark {

MatrixX3dR add_noise(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T, NoiseKind kind,
                     double A, std::uint64_t seed) {
  if (!(A >= 0) || !std::isfinite(A)) {
    std::ostringstream s;
    s << "noise strength must be a finite number >= 0 (a fraction: 0.0025 = 0.25 %), got " << A;
    throw MeshError(s.str());
  }
  const Eigen::Index n = V.rows();
  std::vector<char> used(static_cast<size_t>(n), 0);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[T(f, k)] = 1;
  // d-bar of eq. 6.3.12 over the referenced vertices
  Eigen::Index nu = 0;
  for (char u : used) nu += u;
  MatrixX3dR Vu(nu, 3);
  for (Eigen::Index i = 0, j = 0; i < n; ++i)
    if (used[i]) Vu.row(j++) = V.row(i);
  const double amp = A * mean_centroid_distance(Vu);

  MatrixX3dR out = V;
  Rng rng(seed);
  MatrixX3dR N;
  if (kind == NoiseKind::Normal || kind == NoiseKind::Tangent) N = vertex_normals(V, T);
  for (Eigen::Index i = 0; i < n; ++i) {
    switch (kind) {
      case NoiseKind::Uniform: {  // eq. 6.3.12: x' = x + a d, a ~ U[-A, A]
        const double x = rng.uniform(-1, 1), y = rng.uniform(-1, 1), z = rng.uniform(-1, 1);
        if (used[i]) {
          out(i, 0) += amp * x;
          out(i, 1) += amp * y;
          out(i, 2) += amp * z;
        }
        break;
      }
      case NoiseKind::Gaussian: {
        const double x = rng.normal(), y = rng.normal(), z = rng.normal();
        if (used[i]) {
          out(i, 0) += amp * x;
          out(i, 1) += amp * y;
          out(i, 2) += amp * z;
        }
        break;
      }
      case NoiseKind::Normal: {
        const double a = rng.uniform(-1, 1);
        if (used[i]) out.row(i) += (amp * a) * N.row(i);
        break;
      }
      case NoiseKind::Tangent: {
        Eigen::RowVector3d u(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const Eigen::RowVector3d nn = N.row(i);
        if (used[i] && nn.squaredNorm() > 0) out.row(i) += amp * (u - u.dot(nn) * nn);
        break;
      }
    }
  }
  return out;
}

}  // namespace meshmark
