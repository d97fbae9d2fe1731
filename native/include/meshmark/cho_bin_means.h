// meshmark: count and mean normalised norm of every bin of Cho's K-bin histogram (thesis eq. 6.4.13).
//
// Bin k of K holds the norms with min(max(floor((rho - rho_min) / W), 0), K - 1) == k, W = (rho_max -
// rho_min) / K (exactly the assignment of cho_watermark.h), and its mean is that of the normalised
// norms x = (rho - rho_min - k W) / W (eq. 6.4.13), clamped to [0, 1]. Empty bins get count 0 and mean
// 0. O(K log n) from the sorted norms of cho_norms.h.
#pragma once
#include "meshmark/cho_norms.h"

#include <vector>

namespace meshmark {

void cho_bin_means(const ChoNorms& norms, int K, std::vector<double>& mean, std::vector<int>& count);

}  // namespace meshmark
