// meshmark: Cho, Prost & Jung's vertex-norm watermarks (IEEE TSP 55(1), 2007), as summarised in thesis
// §2.2.2 (Figs. 2.4-2.5) and specified in docs/radial.md §1 ("Cho step n" below).
//
// The norms rho_i = ||v_i - c|| about the centre of gravity c are split into K bins of equal range,
// normalised to [0, 1] inside their bin, and bin n carries one bit w = +1/-1 through a histogram
// mapping with exponent k_n, searched in steps of delta_k until
//   method I  (mean):     mean x'      >= 1/2 + alpha (w = +1)  or <= 1/2 - alpha (w = -1),  x' = x^k;
//   method II (variance): mean (2x'-1)^2 >= 1/3 + alpha (w = +1) or <= 1/3 - alpha (w = -1),
//                         2x'-1 = sgn(y)|y|^k with y = 2x - 1.
// Extraction compares the bin statistic with 1/2 (resp. 1/3). Bins are 0-based.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

enum class ChoMethod { Mean, Variance };

struct ChoBins {
  VectorXi bin;        // (n,) bin of each vertex; -1 for masked-out vertices and the two reference vertices
                       // (Cho's strict inequalities, Cho step 2): the first vertex at rho_min and the first
                       // at rho_max; vertices tied with them stay in the end bins (docs/radial.md)
  Eigen::VectorXd x;   // (n,) norm normalised with its bin's range, in [0, 1] (Cho step 3); 0 when bin -1
  VectorXi counts;     // (K,) vertices per bin
  double rho_min = 0, rho_max = 0, width = 0;  // width W = (rho_max - rho_min) / K
  int K = 0;
};

// Cho steps 2-3 on the norms rho of the vertices with mask != 0. MeshError when K < 1, when fewer
// vertices than bins are given, or when all norms are equal.
ChoBins cho_bins(const Eigen::Ref<const Eigen::VectorXd>& rho, int K, const Eigen::Ref<const VectorXb>& mask);

// (K,) bin statistics of un-mapped values: mean x (method I, eq. 6.4.13) or mean (2x-1)^2 (method II);
// 0 for empty bins.
Eigen::VectorXd cho_statistics(const ChoBins& bins, ChoMethod method);

struct ChoStatistics {
  Eigen::VectorXd stat;    // (K,) as cho_statistics(bins, method)
  VectorXi counts;         // (K,) vertices per bin
  Eigen::Vector3d center;  // the masked centroid (Cho step 1)
};

// Cho steps 1-3 and the bin statistics straight from V, the blind detector: the same numbers as
// cho_statistics(cho_bins(radial_distances(V, mask, c), K, mask), method) with c the masked centroid,
// in three passes over V and no per-vertex storage. Same errors as cho_bins.
ChoStatistics cho_statistics(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                             ChoMethod method);

struct ChoEmbedOptions {
  ChoMethod method = ChoMethod::Mean;
  double alpha = 0.04;     // strength factor (thesis §7.4.4: 0.04 for the mean method)
  double delta_k = 0.001;  // step of k (thesis §8.2)
  double k_max = 100.0;    // largest exponent tried for w = -1 (the smallest is delta_k for w = +1)
  double guard = 0.0;      // > 0: mapped values of modified bins clipped to [guard, 1-guard] (not in the paper)
  int center_iters = 0;    // > 0: re-embed about the marked mesh's centre until it agrees (not in the paper)
};

struct ChoEmbedResult {
  MatrixX3dR V;             // marked vertices (masked-out and unmodified vertices bit-exact)
  Eigen::VectorXd k;        // (K,) exponent of every bin (1 = untouched)
  std::vector<int> failed;  // bins that could not reach their threshold (empty, or k limits hit)
  Eigen::Vector3d center;   // centre used for the returned embedding
  double drift = 0;         // || centroid(marked) - center ||
  int iterations = 0;       // re-synchronisation rounds run
  int n_moved = 0;          // vertices whose norm changed
  int evaluations = 0;      // bin statistics evaluated by the k search (all bins, last embedding)
};

// Embeds bits[c] (+1 / -1) into bin bins_used[c] (Cho step 4-6). Bins not listed keep k = 1.
ChoEmbedResult cho_embed(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask, int K,
                         const std::vector<int>& bins_used, const std::vector<int>& bits,
                         const ChoEmbedOptions& options);

}  // namespace meshmark
