// meshmark: a two-component 1-D Gaussian mixture fitted by EM, for the steganalyzer of thesis §6.4.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

struct GaussianMixture2 {
  double weight[2] = {0, 0}, mean[2] = {0, 0}, var[2] = {0, 0};
  VectorXi label;          // (n,) most probable component of each value (after a final E-step)
  int n_iter = 0;
  bool converged = false;
  double lower_bound = 0;  // mean log-likelihood per value at the last E-step
  bool ok = false;         // false when the values cannot be split in two (fewer than 2 distinct values)
};

// EM with the same steps, stopping rule and regularisation as sklearn.mixture.GaussianMixture
// (covariance_type "full", n_init 1): start from a hard 2-means partition, then alternate E and M
// steps until the mean log-likelihood changes by less than tol (at most max_iter rounds); nk gets
// 10 * machine epsilon and every variance reg_covar. The start is the *optimal* 2-means split of the
// sorted values (exact in 1-D, deterministic), where sklearn runs a seeded k-means++.
GaussianMixture2 gaussian_mixture_2(const std::vector<double>& x, double reg_covar = 1e-6, double tol = 1e-3,
                                    int max_iter = 100);

// Eq. 6.4.14: Bhattacharyya distance of two 1-D Gaussians.
double bhattacharyya_distance(double mean1, double var1, double mean2, double var2);

}  // namespace meshmark
