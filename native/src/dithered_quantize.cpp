#include "meshmark/dithered_quantize.h"
#include "meshmark/error.h"
#include "meshmark/rng.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace meshmark {

MatrixX3dR dither_bits(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXi>& t,
                       const Eigen::Ref<const Eigen::Matrix<std::uint64_t, Eigen::Dynamic, 3, Eigen::RowMajor>>& words,
                       DitherWord word) {
  const Eigen::Index n = V.rows();
  if (t.size() != n || words.rows() != n)
    throw MeshError("dither_bits: t must have one entry and words one row per vertex");
  const int tmax = word == DitherWord::Fixed32 ? 32 : 64;
  for (Eigen::Index i = 0; i < n; ++i)
    if (t[i] < 0 || t[i] > tmax)
      throw MeshError("dither_bits: t[" + std::to_string(i) + "] = " + std::to_string(t[i]) + " is outside 0.." +
                      std::to_string(tmax));
  MatrixX3dR out(n, 3);
  if (word == DitherWord::Float64) {  // ch. 3, 3.2.1: the 64-bit pattern, keep the t leading bits
    for (Eigen::Index i = 0; i < n; ++i) {
      const int nlow = 64 - t[i];
      const std::uint64_t low = nlow >= 64 ? ~std::uint64_t(0) : ((std::uint64_t(1) << nlow) - 1);
      for (int a = 0; a < 3; ++a) {
        std::uint64_t w;
        const double x = V(i, a);
        std::memcpy(&w, &x, 8);
        w = (w & ~low) | (words(i, a) & low);
        double y;
        std::memcpy(&y, &w, 8);
        out(i, a) = y;
      }
    }
    return out;
  }
  // ch. 4 (4.3.1-4.3.2): 32-bit fixed point in the bounding cube of side L
  if (n == 0) return out;
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  const double L = (V.colwise().maxCoeff() - lo).maxCoeff();
  if (!(L > 0)) return V;
  const double scale = std::ldexp(1.0, 32);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int nlow = 32 - t[i];
    const std::uint64_t low = (std::uint64_t(1) << nlow) - 1;
    for (int a = 0; a < 3; ++a) {
      const double s = std::floor((V(i, a) - lo[a]) / L * scale);
      const std::uint64_t q = static_cast<std::uint64_t>(std::min(std::max(s, 0.0), scale - 1));
      const std::uint64_t q2 = (q & ~low) | (words(i, a) & low);
      out(i, a) = lo[a] + L * (static_cast<double>(q2) / scale);
    }
  }
  return out;
}

MatrixX3dR dithered_quantize(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXi>& t,
                             std::uint64_t seed, DitherWord word) {
  Rng rng(seed);
  Eigen::Matrix<std::uint64_t, Eigen::Dynamic, 3, Eigen::RowMajor> W(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int a = 0; a < 3; ++a) W(i, a) = rng.bits();
  return dither_bits(V, t, W, word);
}

}  // namespace meshmark
