// Built with -fno-trapping-math (CMakeLists.txt), without which GCC does not if-convert the selects
// below and leaves the loops scalar.
#include "meshmark/vector_math.h"

#include <cstdint>
#include <cstring>
#include <limits>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define MESHMARK_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MESHMARK_CLONES
#endif

namespace meshmark {

namespace {

inline double as_double(std::uint64_t u) {
  double d;
  std::memcpy(&d, &u, sizeof d);
  return d;
}

inline std::uint64_t as_bits(double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}

// exp(x): x = n ln 2 + r with |r| <= ln(2)/2 (Cody-Waite split of ln 2), e^r by its Taylor series to
// r^13 (truncation < 1e-17), times 2^n built from the low bits of the rounding shifter. 0 below -708.
inline double exp1(double x) {
  constexpr double log2e = 1.4426950408889634, ln2_hi = 6.93147180369123816490e-01,
                   ln2_lo = 1.90821492927058770002e-10, shifter = 6755399441055744.0;  // 1.5 * 2^52
  const double xc = x > -708.0 ? x : -708.0;
  const double t = xc * log2e + shifter;  // round to nearest: n = t - shifter
  const double n = t - shifter;
  const double r = (xc - n * ln2_hi) - n * ln2_lo;
  constexpr double c[14] = {1.0 / 6227020800.0, 1.0 / 479001600.0, 1.0 / 39916800.0, 1.0 / 3628800.0,
                            1.0 / 362880.0,     1.0 / 40320.0,     1.0 / 5040.0,      1.0 / 720.0,
                            1.0 / 120.0,        1.0 / 24.0,        1.0 / 6.0,         0.5,
                            1.0,                1.0};  // 1/13!, ..., 1/1!, 1/0!
  double p = c[0];
  for (int i = 1; i < 14; ++i) p = p * r + c[i];
  const double v = p * as_double((as_bits(t) + 1023) << 52);  // 2^n: n sits in the low bits of t
  return x > -708.0 ? v : 0.0;
}

// ln x: x = 2^e m with m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s), s = (m-1)/(m+1), by its series
// to s^25 (|s| <= 0.172, truncation < 1e-20); e ln 2 with a split ln 2. Subnormals are scaled by 2^54.
inline double log1(double x) {
  constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
  const bool tiny = x < 2.2250738585072014e-308;
  const std::uint64_t b = as_bits(tiny ? x * 18014398509481984.0 : x);  // 2^54
  const double biased = as_double((b >> 52) | 0x4330000000000000ULL) - 4503599627370496.0;  // exponent field
  double m = as_double((b & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);               // [1, 2)
  const bool big = m > 1.4142135623730951;
  m = big ? 0.5 * m : m;
  const double e = biased - 1023.0 + (big ? 1.0 : 0.0) - (tiny ? 54.0 : 0.0);
  const double f = m - 1.0, s = f / (2.0 + f), z = s * s;
  constexpr double c[12] = {1.0 / 25, 1.0 / 23, 1.0 / 21, 1.0 / 19, 1.0 / 17, 1.0 / 15,
                            1.0 / 13, 1.0 / 11, 1.0 / 9,  1.0 / 7,  1.0 / 5,  1.0 / 3};
  double p = c[0];
  for (int i = 1; i < 12; ++i) p = p * z + c[i];
  const double lnm = 2.0 * s + 2.0 * s * (z * p);
  const double r = e * ln2_hi + (e * ln2_lo + lnm);
  return x == 0.0 ? -std::numeric_limits<double>::infinity() : r;
}

}  // namespace

MESHMARK_CLONES void exp_scaled(const double* l, double k, double* out, std::size_t n) {
  for (std::size_t j = 0; j < n; ++j) out[j] = exp1(k * l[j]);
}

MESHMARK_CLONES void log_inplace(double* x, std::size_t n) {
  for (std::size_t j = 0; j < n; ++j) x[j] = log1(x[j]);
}

MESHMARK_CLONES double log_inplace_moment(double* x, std::size_t n, int p) {
  constexpr int L = 8;  // independent partial sums, so that the loop vectorises without reassociation
  double acc[L] = {};
  std::size_t j = 0;
  for (; j + L <= n; j += L)
    for (int t = 0; t < L; ++t) {
      const double v = x[j + t], l = log1(v), w = p == 1 ? v : v * v;
      acc[t] += v > 0 ? w * l : 0.0;
      x[j + t] = l;
    }
  double s = 0;
  for (; j < n; ++j) {
    const double v = x[j], l = log1(v), w = p == 1 ? v : v * v;
    s += v > 0 ? w * l : 0.0;
    x[j] = l;
  }
  for (int t = 0; t < L; ++t) s += acc[t];
  return s;
}

}  // namespace meshmark
