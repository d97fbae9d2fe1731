// meshmark: the normalisation of the stabilised steganalysis sets (YANG208, LFS76s, NVT36s): thesis
// §8.1.1's PCA frame and unit cube, made canonical where the principal axes are not determined.
#pragma once
#include "meshmark/mesh.h"

#include <array>

namespace meshmark {

// Relative eigen-gap below which two principal axes count as one degenerate group: axes k and k+1 share
// a group when lambda_k - lambda_{k+1} <= kFrameDegenerateGap * lambda_1. Within a group the axes are
// arbitrary (a rotation of the mesh turns them), so the feature sets use only quantities that do not
// depend on them (pooled_abs); at the gap the axes are determined to ~1e-3 / 1e-3 * float32 noise.
constexpr double kFrameDegenerateGap = 1e-3;

struct FeatureFrame {
  MatrixX3dR X;                 // (n, 3) every vertex in the frame (unselected rows too)
  std::array<int, 3> group{};   // group[k]: the first axis of the group of axis k (k itself when determined)
  Eigen::RowVector3d centroid;  // of the selected rows, in the frame
  Eigen::Vector3d lambda;       // variances along the axes, descending (frame units)
};

// unit_cube_normalize.h (extended precision, pca.h's sign rule) when the three eigenvalues are apart:
// axes q1, q2, q3, scale so that the largest bounding-box side of the selected rows is 1, box centred
// at (0.5, 0.5, 0.5). For a degenerate group G the "side" is 2 max_i ||p_i^G|| (the diameter of the
// centroid's enclosing ball within the group's subspace, which no rotation of the mesh changes) and the
// group's coordinates are centred on the centroid (+ 0.5). MeshError as unit_cube_normalize.
FeatureFrame feature_frame(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

// |d_k| per axis, with the axes of a degenerate group pooled: ||d_G|| / sqrt(|G|) for each k in G.
Eigen::RowVector3d pooled_abs(const FeatureFrame& fr, const Eigen::Ref<const Eigen::RowVector3d>& d);

}  // namespace meshmark
