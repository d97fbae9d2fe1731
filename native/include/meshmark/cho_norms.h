// meshmark: the vertex norms about the centre of gravity, sorted once, as the §6.4 steganalyzer scans
// every bin number K (thesis eq. 6.4.13; docs/radial.md §3).
//
// Cho's binning (cho_watermark.h) leaves the first vertex at rho_min and the first at rho_max out of
// every bin; the other masked norms are kept sorted with the prefix sums of (rho - rho_min), so the
// count and the mean normalised norm of any bin of any K come from two binary searches and a
// difference (cho_bin_means.h) instead of a pass over the vertices.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

struct ChoNorms {
  double lo = 0, hi = 0;            // rho_min, rho_max (Cho's reference vertices)
  std::vector<double> r;            // the other masked norms, ascending
  std::vector<long double> prefix;  // (r.size() + 1,) prefix[i] = sum_{t < i} (r[t] - lo)
};

// MeshError when no vertex is masked or all are at the same distance from the centre (to 1e-10
// relative): nothing to bin.
ChoNorms cho_norms(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

}  // namespace meshmark
