// meshmark: distances of the (masked) vertices from a centre, the common input of the radial
// watermarks of thesis ch. 6 (Cho et al.'s mean/variance methods, Yang's PCA-origin method) and of
// the specific steganalyzer of §6.4.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// Mean of the rows of V with mask[i] != 0 (Cho's "centre of gravity"). MeshError if none.
Eigen::Vector3d masked_centroid(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

// rho_i = ||v_i - c|| (eq. 6.1.1); 0 where mask[i] == 0.
Eigen::VectorXd radial_distances(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
                                 const Eigen::Vector3d& c);

// v'_i = c + (rho'_i / rho_i)(v_i - c) for the rows with rho'_i != rho_i: a purely radial move that
// keeps theta and phi of eq. 6.1.1; every other row is copied bit-exactly.
MatrixX3dR radial_rescale(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Vector3d& c,
                          const Eigen::Ref<const Eigen::VectorXd>& rho, const Eigen::Ref<const Eigen::VectorXd>& rho_new);

}  // namespace meshmark
