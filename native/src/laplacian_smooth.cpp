#include "meshmark/laplacian_smooth.h"
#include "meshmark/error.h"

#include <cmath>
#include <vector>

namespace meshmark {

MatrixX3dR laplacian_smooth(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, double lambda,
                            int iterations, const VectorXi& fixed) {
  if (!std::isfinite(lambda)) throw MeshError("smoothing factor lambda must be finite");
  if (iterations < 0) throw MeshError("smoothing iterations must be >= 0, got " + std::to_string(iterations));
  const Eigen::Index n = V.rows();
  std::vector<char> moves(static_cast<size_t>(n), 1);
  for (Eigen::Index k = 0; k < fixed.size(); ++k) moves[fixed[k]] = 0;
  MatrixX3dR X = V, Y(n, 3);
  for (int it = 0; it < iterations; ++it) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const Offset b = A.ptr[i], e = A.ptr[i + 1];
      double x = X(i, 0), y = X(i, 1), z = X(i, 2);
      if (e > b && moves[i]) {
        double sx = 0, sy = 0, sz = 0;
        for (Offset k = b; k < e; ++k) {
          const Index j = A.nbr[k];
          sx += X(j, 0);
          sy += X(j, 1);
          sz += X(j, 2);
        }
        const double inv = 1.0 / static_cast<double>(e - b);
        // v_i + lambda (mean of neighbours - v_i): the umbrella operator
        x += lambda * (sx * inv - x);
        y += lambda * (sy * inv - y);
        z += lambda * (sz * inv - z);
      }
      Y(i, 0) = x;
      Y(i, 1) = y;
      Y(i, 2) = z;
    }
    X.swap(Y);
  }
  return X;
}

}  // namespace meshmark
