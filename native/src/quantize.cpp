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
      // the levels of MEPP's CoordinateQuantization (Wang et al. 2010 benchmark), ties down; computed
      // as lo + k step from the integer k so that each level has exactly one floating-point value
      const double u = (V(i, a) - lo) / step;
      double k = std::floor(u);
      if (u - k > 0.5) k += 1;
      out(i, a) = lo + k * step;
    }
  }
  return out;
}

}  // namespace meshmark
