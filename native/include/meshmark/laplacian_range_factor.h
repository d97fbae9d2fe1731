// meshmark: the range factor of the Laplacian watermark's extraction (docs/laplacian.md, "Beyond the
// thesis" (c)). A deformation or smoothing changes the mean edge length, the scale unit of the
// normalised Laplacian lengths, by up to a few per cent, which shifts far bins by several bin widths.
// Extraction therefore tries the ranges (t lo, t hi) for t near 1 and keeps the one whose carrier
// pairs read with the largest mean relative margin |c1 - c2| / (c1 + c2). The score ignores the bit
// values, so it is the same for every key.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

// Counts |B_k|, |B_k+1| of the carrier pairs `ids` (pair j = bins 2j+1, 2j+2 of K over [lo, hi],
// eqs. 7.1.6-7.1.7) in the ascending lengths `d_sorted`. Bins are half-open [edge_k, edge_k+1),
// matching numpy.searchsorted(side='left').
void laplacian_pair_counts(const Eigen::Ref<const Eigen::VectorXd>& d_sorted, double lo, double hi, int K,
                           const std::vector<long long>& ids, std::vector<long long>& c1,
                           std::vector<long long>& c2);

// The factor t: a coarse grid of 201 values over [1 - span, 1 + span] (and t = 1 itself) scored on
// at most 256 evenly spaced carriers, then 51 values within +-1e-3 of the best scored on all. Returns 1 unless the best score exceeds the score at t = 1 by
// more than min_gain (on small meshes the score is noisy and t = 1 is the better bet).
double laplacian_range_factor(const Eigen::Ref<const Eigen::VectorXd>& d_sorted, double lo, double hi, int K,
                              const std::vector<long long>& ids, double span = 0.1, double min_gain = 0.05);

}  // namespace meshmark
