// meshmark: the Laplacian-coordinate watermark of thesis ch. 7 (Yang, Pintus, Rushmeier, Ivrissimtzis).
//
// The watermark lives in the histogram of the Laplacian lengths d (eq. 7.1.5): K bins between
// lo and hi (eqs. 7.1.6-7.1.7), pairs of adjacent bins (B2,B3), (B4,B5), ... up to K_hat
// (eq. 7.2.12), a bit per valid pair (f >= n_thr, eq. 7.1.8) encoded by which bin is larger
// (eq. 7.1.9). Bins and pairs are 0-based here: pair j is the bins (2j+1, 2j+2), i.e. the thesis'
// (B_{2j+2}, B_{2j+3}).
//
// The Python layer (meshmark.watermark.laplacian) chooses the carriers and the bits (key, payload
// coding) and normalises d by the mean edge length; this layer only does the per-element work.
#pragma once
#include "meshmark/laplacian_carrier.h"
#include "meshmark/mesh.h"
#include "meshmark/vertex_adjacency.h"

#include <vector>

namespace meshmark {

struct LaplacianHistogram {
  VectorXi bin;       // (n,) bin of each element, -1 if outside [lo, hi] or excluded
  VectorXi counts;    // (K,) |B_k|
  int K = 0;
  double lo = 0, hi = 0, delta = 0;
  // Number of candidate pairs (K_hat - 1) / 2 with K_hat = 2 floor((K-2)/2) + 1  (eq. 7.2.12)
  int n_pairs() const { return (K - 2) / 2; }
  int pair_size(int j) const { return counts[2 * j + 1] + counts[2 * j + 2]; }  // f (eq. 7.1.8)
};

// Bins of d over [lo, hi] (eqs. 7.1.6, 7.1.7, d_max in B_K). Elements with mask[i] == 0 (e.g.
// unreferenced vertices) or outside [lo, hi] (the extraction rule of §7.3) get bin -1.
LaplacianHistogram laplacian_histogram(const Eigen::Ref<const Eigen::VectorXd>& d, int K, double lo, double hi,
                                       const Eigen::Ref<const VectorXb>& mask);

// The pairs with f >= n_thr (eq. 7.1.8): the embedding capacity is their number.
std::vector<int> valid_pairs(const LaplacianHistogram& h, int n_thr);

struct LaplacianEmbedOptions {
  int n_robust = 5;           // eq. 7.2.16
  double eps = 1e-5;          // eq. 7.1.4
  bool thesis_exact = false;  // true: X^ = (K - eps I)^-1 L^ as in §7.2.2, d measured with the same
                              // eps; false (default): see docs/laplacian.md (margin in every pair,
                              // moved lengths kept off bin edges, zero-mean update solved with +eps)
  double scale = 1.0;         // d used for binning = ||L_i|| / scale (meshmark: mean edge length)
  // Reconstruction when !thesis_exact: iterations <= 0 solves (K + 1e-8 I) dX = dL exactly (CHOLMOD; once for
  // the thesis carrier, in rounds that top up the short pairs for the others, which are not linear in X);
  // iterations > 0 (default) runs rounds of that many PCG steps, re-reading the histogram after each
  // and topping up the pairs that lack part of their margin, at most max_rounds rounds.
  int iterations = 5;
  int max_rounds = 8;
  // The scalar that is binned (laplacian_carrier.h). Thesis: d_i = ||L_i|| / scale from the adjacency,
  // as above. The others are computed by laplacian_carrier() from the adjacency and `triangles` (the
  // mesh's triangles, which must outlive the call; may be empty for Local), and the target values are
  // realised by changing L_i along the field's direction (eq. 7.2.19 generalised).
  LaplacianCarrier carrier = LaplacianCarrier::Thesis;
  double compress = 0.0;  // laplacian_carrier()'s asinh compression (0: none)
  const Eigen::Ref<const MatrixX3iR>* triangles = nullptr;
};

struct LaplacianEmbedResult {
  MatrixX3dR V;               // marked vertices
  Eigen::VectorXd d_target;   // (n,) target lengths d^ (eqs. 7.2.14-7.2.15), in binning units
  int n_moved = 0;            // elements transferred between bins (all rounds)
  int rounds = 0;             // reconstruction rounds (1 for the direct solve)
  int iterations = 0;         // PCG steps over all rounds (0 for the direct solve)
};

// Embeds bits[c] (+1 or -1) into pairs[c] (eqs. 7.2.13-7.2.16, 7.2.19) and reconstructs the
// coordinates with one sparse solve. `hist` is the histogram of the unmarked mesh.
LaplacianEmbedResult laplacian_embed(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A,
                                     const LaplacianHistogram& hist,
                                     const std::vector<int>& pairs, const std::vector<int>& bits,
                                     const LaplacianEmbedOptions& options);

}  // namespace meshmark
