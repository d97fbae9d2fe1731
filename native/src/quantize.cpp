#include "meshmark/quantize.h"
#include "meshmark/error.h"

#include <cmath>

namespace meshmark {

MatrixX3dR quantize(const Eigen::Ref<const MatrixX3dR>& V, int bits) {
  if (bits < 1 || bits > 52) throw MeshError("quantization bits must be 1..52, got " + std::to_string(bits));
  MatrixX3dR out = V;
  if (V.rows() == 0) return out;
  for (int a = 0; a < 3; ++a) {
    const double lo = V.col(a).minCoeff(), hi = V.col(a).maxCoeff();
    const double step = (hi - lo) / std::ldexp(1.0, bits);
    if (!(step > 0)) continue;
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      // MEPP CoordinateQuantization (Wang et al. 2010 benchmark): snap to lo + k step, ties down
      const double x = V(i, a);
      const double xint = std::floor((x - lo) / step) * step + lo;
      out(i, a) = (x - xint <= 0.5 * step) ? xint : xint + step;
    }
  }
  return out;
}

}  // namespace meshmark
