#include "meshmark/cho_norms.h"
#include "meshmark/error.h"
#include "meshmark/radial_distances.h"

#include <algorithm>

namespace meshmark {

ChoNorms cho_norms(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  const Eigen::Vector3d c = masked_centroid(V, mask);
  Eigen::VectorXd rho(V.rows());
  const RadialRange rr = radial_range(V, mask, c, rho.data());
  if (rr.m == 0) throw MeshError("no vertex to analyse");
  if (!(rr.hi - rr.lo > 1e-10 * rr.hi))  // equal up to rounding
    throw MeshError("all vertices are at the same distance from the centre: nothing to analyse");
  ChoNorms s;
  s.lo = rr.lo;
  s.hi = rr.hi;
  s.r.reserve(static_cast<size_t>(rr.m));
  for (Eigen::Index i = 0; i < V.rows(); ++i)  // Cho's two reference vertices belong to no bin
    if (mask[i] && i != rr.i_lo && i != rr.i_hi) s.r.push_back(rho[i]);
  std::sort(s.r.begin(), s.r.end());
  s.prefix.resize(s.r.size() + 1);
  s.prefix[0] = 0;
  for (size_t i = 0; i < s.r.size(); ++i) s.prefix[i + 1] = s.prefix[i] + static_cast<long double>(s.r[i] - s.lo);
  return s;
}

}  // namespace meshmark
