#include "meshmark/cho_bin_means.h"

#include <algorithm>

namespace meshmark {

void cho_bin_means(const ChoNorms& s, int K, std::vector<double>& mean, std::vector<int>& count) {
  mean.assign(K, 0.0);
  count.assign(K, 0);
  const double W = (s.hi - s.lo) / K;
  auto bin = [&](double x) {  // the assignment of cho_watermark.h: floor, clamped
    const int k = static_cast<int>((x - s.lo) / W);
    return std::min(std::max(k, 0), K - 1);
  };
  // bin() is non-decreasing along the sorted norms: each bin is one run, whose end is found by an
  // exponential then a binary search from its start (O(log run length))
  auto first = s.r.begin();
  const auto end = s.r.end();
  for (int k = 0; k < K && first != end; ++k) {
    auto in_bin = [&](double x) { return bin(x) <= k; };
    auto last = end;
    if (k < K - 1) {
      std::ptrdiff_t step = 1;
      auto lo = first;
      while (end - lo > step && in_bin(lo[step])) lo += step, step *= 2;
      last = std::partition_point(lo, lo + std::min<std::ptrdiff_t>(step, end - lo), in_bin);
    }
    const size_t a = static_cast<size_t>(first - s.r.begin()), b = static_cast<size_t>(last - s.r.begin());
    if (b > a) {
      const long double n = static_cast<long double>(b - a);
      // sum of x = (rho - lo - k W) / W over the bin (eq. 6.4.13), from the prefix sums of rho - lo
      const long double sx = (s.prefix[b] - s.prefix[a] - n * static_cast<long double>(W) * k) / W;
      mean[k] = std::min(std::max(static_cast<double>(sx / n), 0.0), 1.0);
      count[k] = static_cast<int>(b - a);
    }
    first = last;
  }
}

}  // namespace meshmark
