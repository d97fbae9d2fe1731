// meshmark: the one pseudo-random generator of the library (attacks, sampling).
#pragma once
#include <cmath>
#include <cstdint>
#include <random>

namespace meshmark {

// std::mt19937_64 (a fixed algorithm, identical on every platform) with meshmark's own transforms,
// so that results never depend on the standard library's distributions:
//   uniform01()  = (x >> 11) * 2^-53            in [0, 1), 53 random bits
//   uniform(a,b) = a + (b - a) * uniform01()
//   normal()     = Marsaglia's polar method on u, v = 2 uniform01() - 1 (both values of a pair are
//                  used, the second one cached)
//   below(n)     = unbiased integer in [0, n) by rejection of the top partial range of 2^64
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}

  std::uint64_t bits() { return g_(); }
  double uniform01() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }
  double uniform(double a, double b) { return a + (b - a) * uniform01(); }

  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform01() - 1.0;
      v = 2.0 * uniform01() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * f;
    has_spare_ = true;
    return u * f;
  }

  std::uint64_t below(std::uint64_t n) {
    if (n <= 1) return 0;
    const std::uint64_t limit = UINT64_MAX - (UINT64_MAX % n + 1) % n;  // accept x <= limit
    std::uint64_t x;
    do x = g_(); while (x > limit);
    return x % n;
  }

 private:
  std::mt19937_64 g_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace meshmark
