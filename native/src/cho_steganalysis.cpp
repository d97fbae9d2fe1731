#include "meshmark/cho_steganalysis.h"
#include "meshmark/error.h"
#include "meshmark/gaussian_mixture.h"
#include "meshmark/radial_distances.h"

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
  const Eigen::Vector3d c = masked_centroid(V, mask);
  const Eigen::VectorXd rho = radial_distances(V, mask, c);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  Eigen::Index i_lo = -1, i_hi = -1;
  for (Eigen::Index i = 0; i < rho.size(); ++i)
    if (mask[i]) {
      if (rho[i] < lo) lo = rho[i], i_lo = i;
      if (rho[i] > hi) hi = rho[i], i_hi = i;
    }
  if (!(hi - lo > 1e-10 * hi))  // equal up to rounding
    throw MeshError("all vertices are at the same distance from the centre: nothing to analyse");
  std::vector<double> r;  // Cho's two reference vertices belong to no bin (as in cho_bins)
  r.reserve(rho.size());
  for (Eigen::Index i = 0; i < rho.size(); ++i)
    if (mask[i] && i != i_lo && i != i_hi) r.push_back(rho[i]);

  ChoSteganalysisResult out;
  out.D = Eigen::VectorXd::Constant(o.K_max - o.K_min + 1, -std::numeric_limits<double>::infinity());
  std::vector<double> sum, means;
  std::vector<int> cnt;
  GaussianMixture2 best_fit;
  std::vector<double> best_means;
  for (int K = o.K_min; K <= o.K_max; ++K) {
    const double W = (hi - lo) / K;
    sum.assign(K, 0.0);
    cnt.assign(K, 0);
    for (const double x : r) {  // the binning and normalisation of cho_bins
      int k = static_cast<int>((x - lo) / W);  // floor: x >= lo
      k = std::min(std::max(k, 0), K - 1);
      sum[k] += std::min(std::max((x - (lo + W * k)) / W, 0.0), 1.0);
      ++cnt[k];
    }
    means.clear();
    for (int k = 0; k < K; ++k)
      if (cnt[k] > 0) means.push_back(sum[k] / cnt[k]);  // eq. 6.4.13
    if (static_cast<int>(means.size()) < std::max(o.min_bins, 2)) continue;
    GaussianMixture2 g = gaussian_mixture_2(means, o.reg_covar);
    if (!g.ok) continue;
    const int n1 = static_cast<int>(g.label.sum()), n0 = static_cast<int>(means.size()) - n1;
    if (std::min(n0, n1) < 2) continue;
    const double D = bhattacharyya_distance(g.mean[0], g.var[0], g.mean[1], g.var[1]);  // eq. 6.4.14
    out.D[K - o.K_min] = D;
    if (out.K_estimate == 0 || D > out.D_max) {  // eq. 6.4.15 (first maximum)
      out.K_estimate = K;
      out.D_max = D;
      best_fit = g;
      best_means = means;
    }
  }
  if (out.K_estimate == 0) return out;
  const int hi_c = best_fit.mean[1] > best_fit.mean[0] ? 1 : 0;  // C: the cluster of larger mean
  out.min_C = std::numeric_limits<double>::infinity();
  out.max_Ctilde = -std::numeric_limits<double>::infinity();
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
