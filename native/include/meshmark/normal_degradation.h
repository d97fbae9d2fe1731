// meshmark: the normal degradation dis(M, M') of thesis eq. 3.2.2 and its weights (eq. 3.2.3).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

enum class NormalWeighting {
  Mean,      // w_i = 1 (dis^av)
  Area,      // w_i = area of triangle i in M (dis^ar)
  Dihedral,  // w_i = exp(-(x_i - mu)^2 / (2 sigma^2)) / sqrt(2 pi sigma^2), eq. 3.2.3 (dis^an)
};

// x_i of eq. 3.2.3, in degrees: for each triangle, the smallest angle between its normal and the
// normal of a triangle sharing an edge with it (0 = coplanar, 180 = folded back). Triangles with no
// usable neighbour (only boundary edges, or zero normals) get +inf (weight 0).
Eigen::VectorXd min_dihedral_angles_deg(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

struct NormalDegradation {
  double value = 0;          // dis(M, M') in radians
  Eigen::VectorXd angle;     // (t,) angle(n_i, n'_i) = atan2(|n x n'|, n . n') in [0, pi]
  Eigen::VectorXd weight;    // (t,) w_i (0 for excluded triangles)
  Eigen::Index n_excluded = 0;  // triangles with a zero or non-finite normal in M or M'
};

// dis(M, M') = sum_i w_i angle(n_i, n'_i) / sum_i w_i                                    (eq. 3.2.2)
// over the triangles T shared by M = (V, T) and M' = (V2, T); sigma and mu in degrees (thesis:
// mu = 0, sigma = 3.5). NaN if every weight is 0. MeshError if V and V2 differ in shape.
NormalDegradation normal_degradation(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3dR>& V2,
                                     const Eigen::Ref<const MatrixX3iR>& T, NormalWeighting weighting,
                                     double mu = 0.0, double sigma = 3.5);

}  // namespace meshmark
