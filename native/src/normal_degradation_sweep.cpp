#include "meshmark/normal_degradation_sweep.h"
#include "meshmark/dithered_quantize.h"
#include "meshmark/error.h"
#include "meshmark/face_areas.h"
#include "meshmark/normal_degradation.h"

#include <cmath>
#include <limits>
#include <string>

namespace meshmark {

std::uint64_t sweep_seed(std::uint64_t seed, int t, int r) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (1 + static_cast<std::uint64_t>(t) + 65ull * static_cast<std::uint64_t>(r));
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;  // splitmix64 finalizer
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

NormalDegradationSweep normal_degradation_sweep(const Eigen::Ref<const MatrixX3dR>& V,
                                                const Eigen::Ref<const MatrixX3iR>& T, const Eigen::Ref<const VectorXi>& t,
                                                std::uint64_t seed, int repeats, double mu, double sigma) {
  if (repeats < 1) throw MeshError("repeats must be >= 1, got " + std::to_string(repeats));
  if (!(sigma > 0)) throw MeshError("sigma must be > 0");
  for (Eigen::Index j = 0; j < t.size(); ++j)
    if (t[j] < 0 || t[j] > 64) throw MeshError("level t = " + std::to_string(t[j]) + " is outside 0..64");
  const Eigen::Index nt = T.rows(), k = t.size();
  // the weights of eq. 3.2.3 depend on M only
  const Eigen::VectorXd area = face_areas(V, T);
  const Eigen::VectorXd x = min_dihedral_angles_deg(V, T);
  const double g = 1.0 / std::sqrt(2 * M_PI * sigma * sigma);
  Eigen::VectorXd wdih(nt);
  for (Eigen::Index f = 0; f < nt; ++f)
    wdih[f] = std::isfinite(x[f]) ? g * std::exp(-(x[f] - mu) * (x[f] - mu) / (2 * sigma * sigma)) : 0.0;
  NormalDegradationSweep out;
  out.mean = decltype(out.mean)::Zero(k, 3);
  out.variance = decltype(out.variance)::Zero(k, 3);
  out.excluded = Eigen::VectorXd::Zero(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero(), s2 = Eigen::Vector3d::Zero();
    for (int r = 0; r < repeats; ++r) {
      const VectorXi tv = VectorXi::Constant(V.rows(), t[j]);
      const MatrixX3dR V2 = dithered_quantize(V, tv, sweep_seed(seed, t[j], r), DitherWord::Float64);
      const NormalDegradation d = normal_degradation(V, V2, T, NormalWeighting::Mean);
      double sw[3] = {0, 0, 0}, swa[3] = {0, 0, 0};
      for (Eigen::Index f = 0; f < nt; ++f) {
        if (!(d.weight[f] > 0)) continue;  // excluded triangle (zero or non-finite normal)
        const double w[3] = {1.0, area[f], wdih[f]}, a = d.angle[f];
        for (int c = 0; c < 3; ++c) {
          sw[c] += w[c];
          swa[c] += w[c] * a;
        }
      }
      for (int c = 0; c < 3; ++c) {
        const double v = sw[c] > 0 ? swa[c] / sw[c] : std::numeric_limits<double>::quiet_NaN();  // eq. 3.2.2
        s[c] += v;
        s2[c] += v * v;
      }
      out.excluded[j] += static_cast<double>(d.n_excluded) / static_cast<double>(std::max<Eigen::Index>(nt, 1));
    }
    for (int c = 0; c < 3; ++c) {
      out.mean(j, c) = s[c] / repeats;
      out.variance(j, c) = repeats > 1 ? std::max(0.0, (s2[c] - s[c] * s[c] / repeats) / (repeats - 1)) : 0.0;
    }
    out.excluded[j] /= repeats;
  }
  return out;
}

}  // namespace meshmark
