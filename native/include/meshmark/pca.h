// meshmark: principal component analysis of a point set, with a deterministic axis sign.
#pragma once
#include "meshmark/mesh.h"

#include <vector>

namespace meshmark {

struct PCA {
  Eigen::Vector3d centroid;     // mean of the points
  Eigen::Matrix3d axes;         // columns q1, q2, q3: unit principal axes
  Eigen::Vector3d eigenvalues;  // lambda1 >= lambda2 >= lambda3: variances along the axes
  Eigen::Vector3d skewness;     // third central moment of the projections on each axis (after the sign rule: >= 0)
  Eigen::Vector3d proj_min, proj_max;  // range of the projections on each axis (after the sign rule)
};

// PCA of the rows of V (unweighted covariance, divided by n; two passes over the points).
// Sign rule (docs/mesh_model.md): each axis is oriented so that the third central moment of the
// projections on it is positive, i.e. the longer tail of the point distribution lies on the positive
// side. This is invariant under rotation, translation, uniform scaling and reordering. When the
// moment is negligible (|m3| <= 1e-9 * lambda^1.5), the axis points towards the point with the
// largest |projection|; if that also ties, the largest-magnitude component of the axis is positive.
PCA pca(const Eigen::Ref<const MatrixX3dR>& V);

// The same for the rows with mask[i] != 0 only (no copy). If first_projections is
// given it receives (q1 . (v_i - centroid)) of those rows in row order, after the sign rule.
// MeshError when mask and V differ in length or no row is selected.
PCA pca(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask,
        std::vector<double>* first_projections = nullptr);

}  // namespace meshmark
