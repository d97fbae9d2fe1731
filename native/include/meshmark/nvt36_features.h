// meshmark: the NVT36 steganalysis features of Zhou et al. (2019, normal voting tensors), the sound
// version (docs/steganalysis.md §3).
//
// Reference mesh: one step of inverse-distance-weighted vertex smoothing, x_i' = sum_j w_ij x_j /
// sum_j w_ij over the 1-ring, w_ij = 1 / ||x_j - x_i|| (Kroon's smoothpatch, mode 2, one iteration,
// lambda = 1, as in the authors' code). Both meshes in the unit-cube frame of the original
// (unit_cube_normalize.h). Three normal voting tensors, each sum_j w_j n_j n_j^T:
//   1. per face, its edge-adjacent faces, w_j = area_j, divided by sum w_j (bnvt_feat);
//   2. per vertex, its incident faces, w_j = area_j / max area * exp(-3 ||c_j - x_i||) (bnvt_feat2);
//   3. per face, the faces sharing a vertex with it (itself included), w_j = area_j / max area *
//      exp(-3 ||c_j - c_f||) (bnvt_feat3);
// c_j = centroid of face j. The eigenvalues lambda1 >= lambda2 >= lambda3 of each tensor on M and M',
// |lambda_k - lambda_k'|: 9 vectors x 4 log-moments (log(|d| + 1e-7); the published eps = 2^-52 is below the
// eigen-solver noise) = 36. Faces without
// an edge-neighbour (tensor 1) and degenerate faces are left out instead of turning the whole feature
// into 0 as the published NaN rule does.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kNvt36Size = 36;

Eigen::VectorXd nvt36_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
