#include "meshmark/keyed_gaussian.h"
#include "meshmark/parallel_for.h"

#include <cmath>

namespace meshmark {

namespace {
constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

inline std::uint64_t mix(std::uint64_t z) {  // SplitMix64's finaliser (Steele, Lea, Flood 2014)
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
}  // namespace

double keyed_gaussian(std::uint64_t seed, std::int64_t i) {
  const auto c = static_cast<std::uint64_t>(i);
  const double u1 = (static_cast<double>(mix(seed + (2 * c + 1) * kGolden) >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = (static_cast<double>(mix(seed + (2 * c + 2) * kGolden) >> 11) + 0.5) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

Eigen::MatrixXd keyed_gaussians(const std::vector<std::uint64_t>& seeds, Eigen::Index n) {
  Eigen::MatrixXd W(n, static_cast<Eigen::Index>(seeds.size()));
  parallel_for(static_cast<std::int64_t>(seeds.size()), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t j = b; j < e; ++j)
      for (Eigen::Index i = 0; i < n; ++i) W(i, j) = keyed_gaussian(seeds[j], i);
  }, 1);
  return W;
}

Eigen::VectorXd keyed_gaussian_dots(const Eigen::Ref<const Eigen::VectorXd>& u, const std::vector<std::uint64_t>& seeds) {
  Eigen::VectorXd d(static_cast<Eigen::Index>(seeds.size()));
  const Eigen::Index n = u.size();
  parallel_for(static_cast<std::int64_t>(seeds.size()), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t j = b; j < e; ++j) {
      double s = 0;
      for (Eigen::Index i = 0; i < n; ++i)
        if (u[i] != 0) s += u[i] * keyed_gaussian(seeds[j], i);
      d[j] = s;
    }
  }, 1);
  return d;
}

}  // namespace meshmark
