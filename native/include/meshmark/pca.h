// meshmark: principal component analysis of a point set, with a deterministic axis sign.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct PCA {
  Eigen::Vector3d centroid;     // mean of the points
  Eigen::Matrix3d axes;         // columns q1, q2, q3: unit principal axes
  Eigen::Vector3d eigenvalues;  // lambda1 >= lambda2 >= lambda3: variances along the axes
  Eigen::Vector3d skewness;     // third central moment of the projections on each axis (after the sign rule: >= 0)
};

// PCA of the rows of V (unweighted covariance, divided by n; two passes over the points).
// Sign rule (docs/mesh_model.md): each axis is oriented so that the third central moment of the
// projections on it is positive, i.e. the longer tail of the point distribution lies on the positive
// side. This is invariant under rotation, translation, uniform scaling and reordering. When the
// moment is negligible (|m3| <= 1e-9 * lambda^1.5), the axis points towards the point with the
// largest |projection|; if that also ties, the largest-magnitude component of the axis is positive.
PCA pca(const Eigen::Ref<const MatrixX3dR>& V);

// The same for the rows with mask[i] != 0 only (no copy; an empty mask selects every row).
// MeshError when mask and V differ in length or no row is selected.
PCA pca(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

// The two halves of pca(), for callers that fuse more work into the second pass (radial_origin).
// pca_frame: pass 1, centroid and covariance from moments about the first selected point (shifted
// data), eigen-decomposition; axes unoriented, skewness unset. radius is a bound on ||v - centroid||
// over the selected rows. Empty mask = every row.
struct PCAFrame {
  PCA pca;
  Eigen::Index n = 0;  // selected rows
  double radius = 0;
};
PCAFrame pca_frame(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

// The sign rule for one axis q with eigenvalue lambda, given the mean cube m3 and the range
// [pmin, pmax] of the projections on q: +1 or -1.
int pca_axis_sign(double m3, double pmin, double pmax, double lambda, const Eigen::Vector3d& q);

}  // namespace meshmark
