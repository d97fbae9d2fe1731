// meshmark: mean length of the edges of a mesh (the scale unit of the Laplacian watermark).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// Mean of ||V[E(e,0)] - V[E(e,1)]|| over the edges E (model units); 0 for no edges.
double mean_edge_length(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX2iR>& E);

}  // namespace meshmark
