// meshmark: the per-mesh normalisation of the published LFS76 and NVT36 code (preprocess.m, with the
// corrected projection; docs/steganalysis.md §3).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// MATLAB's pca(V) coefficients Q (principal axes of the rows without NaN, centred on their mean, in
// descending order of variance; a column is negated when its largest entry is smaller than the magnitude
// of its smallest, so its largest-magnitude entry is positive), the uncentred projection P = V Q
// (`vertex' * trans`, the corrected form of the published `trans * vertex`), then each column shifted by
// its minimum and all divided by the largest extent: X = (P - min) / max_k (max_k - min_k). Minima and
// maxima skip NaN rows; NaN rows stay NaN. Every row of V takes part (unreferenced vertices too, as in
// the published code). MeshError when no finite row is left or all of them coincide.
MatrixX3dR pca_min_corner_normalize(const Eigen::Ref<const MatrixX3dR>& V);

}  // namespace meshmark
