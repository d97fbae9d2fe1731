// meshmark: the steganalysis normalisation of thesis §8.1.1.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// The vertices in the PCA frame of the rows with mask != 0 (axes q1, q2, q3 for lambda1 >= lambda2 >=
// lambda3, pca.h's sign rule), uniformly scaled so that the largest bounding-box side of the selected
// rows is 1 and translated so that the box is centred at (0.5, 0.5, 0.5) (§8.1.1). Every row is
// transformed (unselected rows too). MeshError when no row is selected or the selected rows coincide.
MatrixX3dR unit_cube_normalize(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXb>& mask);

}  // namespace meshmark
