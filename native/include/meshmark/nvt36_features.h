// meshmark: the NVT36 steganalysis features of Zhou et al. (IEEE TVCG 2019) exactly as the authors' code
// computes them (RyanHangZhou/NVTplus @ 19d0808: nvt36_fea.m, bnvt_feat{,2,3}.m; docs/steganalysis.md §3).
//
// 1. Reference mesh: Kroon's smoothpatch(fv, 2, 1) on the file's coordinates: one umbrella step with
//    inverse-distance weights 1 / (|e| + sigma), sigma = 1 in the file's units (not scale-invariant),
//    each face side counted once per face, lambda = 1; a vertex in no face becomes NaN.
// 2. Each mesh normalised on its own (pca_min_corner_normalize.h: the corrected projection).
// 3. Face normals of compute_normal (toolbox_graph: cross(v1 - v0, v2 - v0) / |.|, a norm below 2^-52 is
//    taken as 1); areas of meshSurfaceAreaList (|c . n| / 2 with n = cross of the normalised edges; NaN -> 0).
// 4. Three normal voting tensors and their eigenvalues (descending):
//    bnvt_feat:  per face with exactly three edges in trimeshEdgeFaces' first two columns, the area-weighted
//                n n^T of the one other face of each edge, divided by (sum of weights + 2^-52); else NaN;
//    bnvt_feat2: per vertex (all of them, in no face: zeros), sum over its faces of
//                area / (max area + 2^-52) * exp(-3 |c_j - v|) n n^T;
//    bnvt_feat3: per face, the same over the faces sharing a vertex with it (itself included), about its centroid.
// 5. |lambda_k - lambda_k'|, then mean, var (N - 1), skewness, kurtosis (biased, not excess) of
//    log(d + 2^-52) per vector; NaN statistics are 0 (F(isnan(F)) = 0).
// Faces must be triangles.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kNvt36Size = 36;

Eigen::VectorXd nvt36_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
