// meshmark: distances of the (masked) vertices from a centre, the common input of the radial
// watermarks of thesis ch. 6 (Cho et al.'s mean/variance methods, Yang's PCA-origin method) and of
// the specific steganalyzer of §6.4.
#pragma once
#include "meshmark/mesh.h"

#include <cmath>

namespace meshmark {

// Pointer to row i of V (x, y, z contiguous; rows may be strided).
inline const double* row_ptr(const Eigen::Ref<const MatrixX3dR>& V, Eigen::Index i) {
  return V.data() + i * V.outerStride();
}

// rho = ||v - c|| (eq. 6.1.1) of the row starting at v, with one fixed order of operations: every
// radial routine (embedders, detectors, steganalyzer) bins exactly the same numbers.
inline double vertex_distance(const double* v, const Eigen::Vector3d& c) {
  const double dx = v[0] - c[0], dy = v[1] - c[1], dz = v[2] - c[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Mean of the rows of V with mask[i] != 0 (Cho's "centre of gravity"). MeshError if none.
Eigen::Vector3d masked_centroid(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

// rho_i = ||v_i - c|| (eq. 6.1.1); 0 where mask[i] == 0.
Eigen::VectorXd radial_distances(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                 const Eigen::Vector3d& c);

// Range of rho = ||v_i - c|| over the masked rows, in one pass: the smallest and largest value, the
// first row attaining each, and the number m of masked rows (0: lo = +inf). When rho is given it
// receives rho_i for every row (0 for masked-out rows).
struct RadialRange {
  double lo = 0, hi = 0;
  Eigen::Index i_lo = -1, i_hi = -1, m = 0;
};
RadialRange radial_range(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                         const Eigen::Vector3d& c, double* rho = nullptr);

// v'_i = c + (rho'_i / rho_i)(v_i - c) for the rows with rho'_i != rho_i: a purely radial move that
// keeps theta and phi of eq. 6.1.1; every other row is copied bit-exactly.
MatrixX3dR radial_rescale(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Vector3d& c,
                          const Eigen::Ref<const Eigen::VectorXd>& rho, const Eigen::Ref<const Eigen::VectorXd>& rho_new);

// Makes out an (n, 3) matrix for output; a fresh buffer gets huge pages advised (huge_pages.h).
// The contents are unspecified.
void prepare_output(MatrixX3dR& out, Eigen::Index n);

// The same move for one row of a copy: out_i = c + (rho_new / rho)(v_i - c) (rho > 0).
inline void radial_move_row(const double* v, double* out, const Eigen::Vector3d& c, double rho, double rho_new) {
  const double s = rho_new / rho;
  for (int j = 0; j < 3; ++j) out[j] = c[j] + (v[j] - c[j]) * s;
}

}  // namespace meshmark
