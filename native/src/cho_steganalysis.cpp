#include "meshmark/cho_steganalysis.h"
#include "meshmark/cho_bin_means.h"
#include "meshmark/cho_margin_test.h"
#include "meshmark/cho_norms.h"
#include "meshmark/error.h"
#include "meshmark/gaussian_mixture.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace meshmark {

ChoSteganalysisResult cho_steganalysis(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                       const ChoSteganalysisOptions& o) {
  if (o.K_min < 1 || o.K_max < o.K_min)
    throw MeshError("need 1 <= K_min <= K_max, got K_min=" + std::to_string(o.K_min) + ", K_max=" +
                    std::to_string(o.K_max));
  if (o.trim < 0 || o.min_count < 1 || o.min_bins < 2 || !(o.eps >= 0) || !(o.eps2 >= 0) ||
      !(o.false_alarm > 0 && o.false_alarm < 1))
    throw MeshError("cho_steganalysis: option out of range");
  const ChoNorms norms = cho_norms(V, mask);
  // a Cho mark has at most one bin per vertex: K beyond the vertex count is not scanned
  const long long n_vertices = static_cast<long long>(norms.r.size()) + 2;
  ChoSteganalysisResult out;
  out.K_max_used = static_cast<int>(std::min<long long>(o.K_max, std::max<long long>(n_vertices, o.K_min)));
  const int nK = out.K_max_used - o.K_min + 1;
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  out.D = Eigen::VectorXd::Constant(nK, -inf);
  out.loglik = Eigen::VectorXd::Constant(nK, nan);
  out.log_p = Eigen::VectorXd::Constant(nK, nan);
  out.hole = Eigen::VectorXd::Constant(nK, nan);
  out.n_bins = VectorXi::Zero(nK);
  std::vector<double> mean, means;
  std::vector<int> cnt;
  GaussianMixture2 best_fit;
  std::vector<double> best_means;
  ChoMarginTest best_margin;
  for (int K = o.K_min; K <= out.K_max_used; ++K) {
    const int j = K - o.K_min;
    cho_bin_means(norms, K, mean, cnt);  // eq. 6.4.13
    // the margin rule
    const ChoMarginTest t = cho_margin_test(mean, cnt, o.trim, o.min_count, o.min_bins);
    out.n_bins[j] = t.n_bins;
    if (t.ok) {
      out.log_p[j] = t.log_p;
      out.hole[j] = t.hole;
      ++out.n_tests;
      if (out.K_margin == 0 || t.log_p < out.log_p_min) {
        out.K_margin = K;
        out.log_p_min = t.log_p;
        best_margin = t;
      }
    }
    if (!o.fit_em) continue;
    // the thesis' rule
    means.clear();
    for (int k = 0; k < K; ++k)
      if (cnt[k] > 0) means.push_back(mean[k]);
    if (static_cast<int>(means.size()) < std::max(o.min_bins, 2)) continue;
    GaussianMixture2 g = gaussian_mixture_2(means, o.reg_covar);
    if (!g.ok) continue;
    const int n1 = static_cast<int>(g.label.sum()), n0 = static_cast<int>(means.size()) - n1;
    if (std::min(n0, n1) < 2) continue;
    const double D = bhattacharyya_distance(g.mean[0], g.var[0], g.mean[1], g.var[1]);  // eq. 6.4.14
    out.D[j] = D;
    out.loglik[j] = g.lower_bound;
    if (out.K_estimate == 0 || D > out.D_max) {  // eq. 6.4.15 (first maximum)
      out.K_estimate = K;
      out.D_max = D;
      best_fit = g;
      best_means = means;
    }
  }
  if (out.n_tests > 0) {
    out.log_p_scan = std::min(0.0, out.log_p_min + std::log(static_cast<double>(out.n_tests)));  // Bonferroni
    out.margin = best_margin.hole;
    out.q = best_margin.q;
    out.margin_bins = best_margin.n_bins;
    out.margin_above = best_margin.n_above;
    out.margin_marked = out.log_p_scan <= std::log(o.false_alarm);
  }
  if (out.K_estimate == 0) return out;
  const int hi_c = best_fit.mean[1] > best_fit.mean[0] ? 1 : 0;  // C: the cluster of larger mean
  out.min_C = inf;
  out.max_Ctilde = -inf;
  for (size_t i = 0; i < best_means.size(); ++i) {
    if (best_fit.label[i] == hi_c) {
      out.min_C = std::min(out.min_C, best_means[i]);
      ++out.size_C;
    } else {
      out.max_Ctilde = std::max(out.max_Ctilde, best_means[i]);
      ++out.size_Ctilde;
    }
  }
  out.eq_6_4_16 = out.min_C > 0.5 && 0.5 > out.max_Ctilde && std::abs(out.min_C + out.max_Ctilde - 1) <= o.eps;
  out.balance = std::abs(out.size_C - out.size_Ctilde) / static_cast<double>(out.K_estimate);
  out.eq_6_4_17 = out.balance <= o.eps2;
  out.marked = out.eq_6_4_16 && out.eq_6_4_17;
  return out;
}

}  // namespace meshmark
