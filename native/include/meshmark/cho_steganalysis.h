// meshmark: the specific steganalyzer against Cho's mean method (thesis §6.4; docs/radial.md §3).
//
// For every candidate bin number K in [K_min, K_max]: Cho's binning and bin-range normalisation of
// the norms about the centroid (see cho_watermark.h), the means m_k of the non-empty bins
// (eq. 6.4.13), a two-Gaussian mixture fitted by EM (gaussian_mixture.h) and the Bhattacharyya
// distance D_K of its components (eq. 6.4.14). K' = argmax D_K (eq. 6.4.15); with C the cluster of
// larger mean and C~ the other, the mesh is declared marked iff
//   eq. 6.4.16: min C > 0.5 > max C~ and |min C + max C~ - 1| <= eps, and
//   eq. 6.4.17: | |C| - |C~| | / K' <= eps2.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

struct ChoSteganalysisOptions {
  int K_min = 1, K_max = 500;
  double eps = 0.15;   // eq. 6.4.16
  double eps2 = 0.03;  // eq. 6.4.17
  int min_bins = 8;    // not in the thesis: K with fewer non-empty bins (or a component with < 2 bins) is skipped
  double reg_covar = 1e-6;
};

struct ChoSteganalysisResult {
  int K_estimate = 0;           // K' (eq. 6.4.15); 0 if no K could be fitted
  double D_max = 0;             // D_K'
  Eigen::VectorXd D;            // (K_max - K_min + 1,) D_K, -inf where skipped
  double min_C = 0, max_Ctilde = 0;
  int size_C = 0, size_Ctilde = 0;
  bool eq_6_4_16 = false, eq_6_4_17 = false, marked = false;
  double balance = 0;           // | |C| - |C~| | / K'
};

ChoSteganalysisResult cho_steganalysis(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                       const ChoSteganalysisOptions& options);

}  // namespace meshmark
