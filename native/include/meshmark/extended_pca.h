#pragma once
// The PCA frame of §8.1.1 in extended precision (docs/steganalysis.md §2, "Invariance"): centroid,
// covariance, eigenvectors (descending eigenvalues) and pca.h's sign rule, accumulated in long double.
// Shared by unit_cube_normalize and feature_frame.
#include "meshmark/mesh.h"

#include <Eigen/Core>

namespace meshmark {

struct ExtendedPca {
  Eigen::Matrix<long double, 3, 1> centroid;  // of the selected vertices
  Eigen::Matrix<long double, 3, 3> axes;      // columns: the signed principal axes, descending
  Eigen::Matrix<long double, 3, 1> lambda;    // the covariance's eigenvalues, descending, >= 0
};

// V (n, 3); mask (n,) selects the vertices (empty: all). MeshError for no selected vertex or a mask of
// another length.
ExtendedPca extended_pca(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

}  // namespace meshmark
