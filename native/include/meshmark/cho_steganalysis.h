// meshmark: the specific steganalyzer against Cho's mean method (thesis §6.4; docs/radial.md §3).
//
// For every candidate bin number K in [K_min, min(K_max, number of masked vertices)]: Cho's binning
// and bin-range normalisation of the norms about the centroid (cho_bin_means.h) and the means m_k of
// the bins (eq. 6.4.13). Two decision rules are evaluated on the same bin means:
//
// * the thesis' rule: a two-Gaussian mixture fitted by EM to the means of the non-empty bins
//   (gaussian_mixture.h) and the Bhattacharyya distance D_K of its components (eq. 6.4.14); K' =
//   argmax D_K (eq. 6.4.15); with C the cluster of larger mean and C~ the other, marked iff
//     eq. 6.4.16: min C > 0.5 > max C~ and |min C + max C~ - 1| <= eps, and
//     eq. 6.4.17: | |C| - |C~| | / K' <= eps2;
//   the fits are run only when fit_em is set.
// * the margin rule (not in the thesis; docs/radial.md §3.2): the margin test of every K
//   (cho_margin_test.h) gives a p-value p_K; K'' = argmin p_K and the mesh is declared marked iff
//   min_K p_K times the number of K tested (Bonferroni over the scan) is <= false_alarm.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

struct ChoSteganalysisOptions {
  int K_min = 1, K_max = 500;
  double eps = 0.15;   // eq. 6.4.16
  double eps2 = 0.03;  // eq. 6.4.17
  int min_bins = 8;    // not in the thesis: K with fewer usable bins (or an EM component with < 2 bins) is skipped
  double reg_covar = 1e-6;
  bool fit_em = true;  // run the thesis' EM fits (D_K, eqs. 6.4.14-17)
  int trim = 3;        // margin rule: bins allowed closer to 1/2 than the margin
  int min_count = 5;   // margin rule: bins with fewer vertices are left out
  double false_alarm = 0.01;  // margin rule: level of the scan
};

struct ChoSteganalysisResult {
  int K_max_used = 0;           // min(K_max, number of masked vertices)
  // --- the thesis' rule
  int K_estimate = 0;           // K' (eq. 6.4.15); 0 if no K could be fitted
  double D_max = 0;             // D_K'
  Eigen::VectorXd D;            // (K_max_used - K_min + 1,) D_K, -inf where skipped
  Eigen::VectorXd loglik;       // mean log-likelihood of the EM fit per K, NaN where skipped
  double min_C = 0, max_Ctilde = 0;
  int size_C = 0, size_Ctilde = 0;
  bool eq_6_4_16 = false, eq_6_4_17 = false, marked = false;
  double balance = 0;           // | |C| - |C~| | / K'
  // --- the margin rule
  Eigen::VectorXd log_p;        // natural log of the margin test's p_K, NaN where no test
  Eigen::VectorXd hole;         // the margin h of each K (NaN where no test)
  Eigen::VectorXi n_bins;       // bins holding >= min_count vertices, per K
  int K_margin = 0;             // argmin p_K (first minimum), 0 if no K was tested
  int n_tests = 0;              // number of K tested
  double log_p_min = 0;         // log p_K at K_margin
  double log_p_scan = 0;        // log(min(1, n_tests * p_min)): the scan's corrected p-value
  double margin = 0, q = 0;     // h and the null probability q at K_margin
  int margin_bins = 0, margin_above = 0;
  bool margin_marked = false;
};

ChoSteganalysisResult cho_steganalysis(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                       const ChoSteganalysisOptions& options);

}  // namespace meshmark
