// meshmark: NVT36s, the stabilised variant of the NVT36 features of Zhou et al. (IEEE TVCG 2019, normal
// voting tensors) that the protocol and the default model use (docs/steganalysis.md §3; the published
// computation is nvt36_features.h).
//
// Reference mesh: one step of inverse-distance-weighted vertex smoothing, x_i' = sum_j w_ij x_j / sum_j
// w_ij over the 1-ring, w_ij = 1 / ||x_j - x_i|| (smoothpatch mode 2 without its sigma = 1 in file units,
// which is not scale-invariant). Both meshes in the frame of the original (feature_frame.h). Three normal
// voting tensors, each sum_j w_j n_j n_j^T:
//   1. per face, its edge-adjacent faces, w_j = area_j / sum area (bnvt_feat);
//   2. per vertex, its incident faces, w_j = area_j / max area * exp(-3 ||c_j - x_i||) (bnvt_feat2);
//   3. per face, the faces sharing a vertex with it (itself included), w_j = area_j / max area *
//      exp(-3 ||c_j - c_f||) (bnvt_feat3);
// c_j = centroid of face j. |lambda_k - lambda_k'| of the sorted eigenvalues: 9 vectors x 4 log-moments
// of the values floored at 10x their float32 storage noise (first-order eigenvalue bounds; elements
// whose floor exceeds 0.1 left out; feature_statistics.h). Faces without an edge-neighbour (tensor 1)
// and degenerate faces are left out instead of turning the whole feature into 0 as the published NaN
// rule does.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kNvt36sSize = 36;

Eigen::VectorXd nvt36s_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
