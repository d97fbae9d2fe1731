#include "meshmark/radial_distances.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"

#include <limits>

namespace meshmark {

Eigen::Vector3d masked_centroid(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  double s0 = 0, s1 = 0, s2 = 0;
  Eigen::Index n = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (mask[i]) {
      const double* p = row_ptr(V, i);
      s0 += p[0];
      s1 += p[1];
      s2 += p[2];
      ++n;
    }
  if (n == 0) throw MeshError("the mesh has no (referenced) vertices");
  return Eigen::Vector3d(s0, s1, s2) / static_cast<double>(n);
}

Eigen::VectorXd radial_distances(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                 const Eigen::Vector3d& c) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (mask[i]) rho[i] = vertex_distance(row_ptr(V, i), c);  // eq. 6.1.1
  return rho;
}

RadialRange radial_range(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                         const Eigen::Vector3d& c, double* rho_out) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
  RadialRange r;
  r.lo = std::numeric_limits<double>::infinity();
  r.hi = -r.lo;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (!mask[i]) {
      if (rho_out) rho_out[i] = 0.0;
      continue;
    }
    ++r.m;
    const double rho = vertex_distance(row_ptr(V, i), c);
    if (rho_out) rho_out[i] = rho;
    if (rho < r.lo) r.lo = rho, r.i_lo = i;
    if (rho > r.hi) r.hi = rho, r.i_hi = i;
  }
  return r;
}

void prepare_output(MatrixX3dR& out, Eigen::Index n) {
  if (out.rows() == n) return;
  out.resize(n, 3);
  advise_huge_pages(out.data(), static_cast<std::size_t>(n) * 3 * sizeof(double));
}

MatrixX3dR radial_rescale(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Vector3d& c,
                          const Eigen::Ref<const Eigen::VectorXd>& rho, const Eigen::Ref<const Eigen::VectorXd>& rho_new) {
  MatrixX3dR out;
  prepare_output(out, V.rows());
  out = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (rho_new[i] != rho[i] && rho[i] > 0) radial_move_row(row_ptr(V, i), &out(i, 0), c, rho[i], rho_new[i]);
  return out;
}

}  // namespace meshmark
