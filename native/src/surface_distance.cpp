#include "meshmark/surface_distance.h"
#include "meshmark/error.h"
#include "meshmark/rng.h"
#include "meshmark/triangle_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace meshmark {

MatrixX3dR sample_surface(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                          Eigen::Index n, std::uint64_t seed, VectorXi* face) {
  const Eigen::Index t = T.rows();
  if (n < 0) throw MeshError("the number of samples must be >= 0");
  if (t == 0 && n > 0) throw MeshError("mesh has no faces to sample");
  std::vector<double> cdf(static_cast<size_t>(t));
  double total = 0;
  for (Eigen::Index f = 0; f < t; ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    total += 0.5 * (b - a).cross(c - a).norm();
    cdf[f] = total;
  }
  if (n > 0 && !(total > 0)) throw MeshError("mesh has zero surface area: nothing to sample");
  Rng rng(seed);
  std::vector<Index> fid(static_cast<size_t>(n));
  std::vector<double> r1(static_cast<size_t>(n)), r2(static_cast<size_t>(n));
  std::vector<Eigen::Index> count(static_cast<size_t>(t) + 1, 0);
  for (Eigen::Index s = 0; s < n; ++s) {
    const double u = rng.uniform01() * total;
    auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
    Eigen::Index f = std::min<Eigen::Index>(it - cdf.begin(), t - 1);
    while (f > 0 && cdf[f] == cdf[f - 1]) --f;  // never land on a zero-area triangle
    fid[s] = static_cast<Index>(f);
    double x = rng.uniform01(), y = rng.uniform01();
    if (x + y > 1) {
      x = 1 - x;
      y = 1 - y;
    }
    r1[s] = x;
    r2[s] = y;
    ++count[f + 1];
  }
  for (Eigen::Index f = 0; f < t; ++f) count[f + 1] += count[f];  // counting sort by triangle
  MatrixX3dR P(n, 3);
  if (face) face->resize(n);
  for (Eigen::Index s = 0; s < n; ++s) {
    const Index f = fid[s];
    const Eigen::Index k = count[f]++;
    const Eigen::RowVector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    P.row(k) = a + r1[s] * (b - a) + r2[s] * (c - a);
    if (face) (*face)[k] = f;
  }
  return P;
}

Eigen::VectorXd point_mesh_distance(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& V,
                                    const Eigen::Ref<const MatrixX3iR>& T, VectorXi* face) {
  if (T.rows() == 0) throw MeshError("mesh has no faces");
  const TriangleTree tree(V, T);
  Eigen::VectorXd d(P.rows());
  if (face) face->resize(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    Index f;
    d[i] = std::sqrt(tree.closest(P.row(i).transpose(), &f));
    if (face) (*face)[i] = f;
  }
  return d;
}

OneSidedDistance one_sided_distance(const Eigen::Ref<const MatrixX3dR>& VA, const Eigen::Ref<const MatrixX3iR>& TA,
                                    const Eigen::Ref<const MatrixX3dR>& VB, const Eigen::Ref<const MatrixX3iR>& TB,
                                    Eigen::Index n_samples, bool include_vertices, std::uint64_t seed) {
  if (TA.rows() == 0 || TB.rows() == 0) throw MeshError("mesh has no faces");
  const TriangleTree tree(VB, TB);
  OneSidedDistance r;
  r.min = HUGE_VAL;
  double sum = 0, sum2 = 0, dmax = 0;
  auto add = [&](const Eigen::Vector3d& p) {
    const double d2 = tree.closest(p);
    const double d = std::sqrt(d2);
    sum += d;
    sum2 += d2;
    dmax = std::max(dmax, d);
    r.min = std::min(r.min, d);
    ++r.n_samples;
  };
  if (include_vertices) {
    std::vector<char> used(static_cast<size_t>(VA.rows()), 0);
    for (Eigen::Index f = 0; f < TA.rows(); ++f)
      for (int k = 0; k < 3; ++k) used[TA(f, k)] = 1;
    for (Eigen::Index i = 0; i < VA.rows(); ++i)
      if (used[i]) add(VA.row(i).transpose());
  }
  if (n_samples > 0) {
    const MatrixX3dR S = sample_surface(VA, TA, n_samples, seed);
    for (Eigen::Index i = 0; i < S.rows(); ++i) add(S.row(i).transpose());
  }
  if (r.n_samples == 0) throw MeshError("no samples: include_vertices is false and n_samples is 0");
  r.max = dmax;
  r.mean = sum / static_cast<double>(r.n_samples);
  r.rms = std::sqrt(sum2 / static_cast<double>(r.n_samples));
  return r;
}

}  // namespace meshmark
