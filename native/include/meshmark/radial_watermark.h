// meshmark: Yang's radial-histogram watermark with a PCA origin (thesis §6.1-6.2; docs/radial.md §2).
//
// rho_i = ||v_i - o|| (eq. 6.1.1) about an origin o on the first principal axis (§6.1.1); K bins of
// width (rho_max - rho_min)/K (eqs. 6.1.2-6.1.3); pairs (B2,B3), (B4,B5), ... with B1, B_K (and
// B_{K-1} when K is odd) never used. Pair j is the 0-based bins (2j+1, 2j+2). A bit is written as
// which bin of the pair is larger (eqs. 6.1.5-6.1.7) and read by eq. 6.2.10:
// w = -1 <=> |B_{k+1}| >= |B_k|, w = +1 <=> |B_k| > |B_{k+1}|.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

enum class RadialOriginMode { Axis, Vertices };

struct RadialOrigin {
  Eigen::Vector3d origin;  // o
  Eigen::Vector3d axis;    // first principal axis u, oriented by meshmark::pca's skewness sign rule
  double skewness = 0;     // standardised skewness m3 / lambda1^1.5 along u (a value near 0 makes o unstable)
};

// §6.1.1: the mean of the right-most half (the floor(N/2) largest projections on u) of the masked
// vertices, either as the point of the axis at that mean projection (Axis, default: "a point
// computed on the principal axis") or as the 3-D mean of those vertices (Vertices).
RadialOrigin radial_origin(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                           RadialOriginMode mode = RadialOriginMode::Axis);

struct RadialHistogram {
  VectorXi bin;     // (n,) 0-based bin, -1 for masked-out vertices
  VectorXi counts;  // (K,)
  double rho_min = 0, rho_max = 0, delta = 0;
  int K = 0;
  int n_pairs() const { return (K - 2) / 2; }  // capacity floor((K-2)/2) (§6.3.1)
};

// Eqs. 6.1.2-6.1.3 (rho_max in B_K). MeshError when K < 4, fewer vertices than bins, or all equal.
RadialHistogram radial_histogram(const Eigen::Ref<const Eigen::VectorXd>& rho, int K,
                                 const Eigen::Ref<const VectorXb>& mask);

struct RadialCounts {
  VectorXi counts;  // (K,)
  double rho_min = 0, rho_max = 0, delta = 0;
};

// The histogram counts about a given origin o straight from V (eqs. 6.1.1-6.1.3), the blind detector
// of eq. 6.2.10: the counts of radial_histogram(radial_distances(V, mask, o), K, mask) in two passes
// without per-vertex storage. Same errors as radial_histogram.
RadialCounts radial_counts(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                           const Eigen::Vector3d& o);

struct RadialEmbedOptions {
  int n_thr = 43;        // eq. 6.1.6 (Table 6.1)
  RadialOriginMode origin_mode = RadialOriginMode::Axis;
  int origin_iters = 0;  // > 0: re-embed about the marked mesh's origin until it agrees (not in the thesis)
  bool first_embeddable = false;  // true: ignore `pairs`, bit i goes to the i-th embeddable pair (eq. 6.1.4)
};

struct RadialEmbedResult {
  MatrixX3dR V;
  Eigen::Vector3d origin;
  std::vector<int> pairs;  // pairs used
  std::vector<int> n_mov;  // per used pair (eq. 6.1.7)
  int n_moved = 0;
  double drift = 0;        // || origin(marked) - origin used ||; -1 (not measured) when origin_iters == 0
  int iterations = 0;
};

// Embeds bits[c] (+1 / -1) into pair pairs[c] (pair j = bins 2j+1, 2j+2): cases 1-3, eqs. 6.1.5-6.1.7.
RadialEmbedResult radial_embed(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                               const std::vector<int>& pairs, const std::vector<int>& bits,
                               const RadialEmbedOptions& options);

}  // namespace meshmark
