// meshmark: the PCA-interval steganography of Chao, Lin, Yu and Lee (IEEE TVCG 15(2), 2009) as thesis
// §8.2 uses it (n_layers = 10, n_intervals = 10000): the baseline of §4.3.2. Interpretation choices
// where the published description is silent: docs/stego.md, "Chao et al. 2009".
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct ChaoFrame {
  Eigen::Vector3d centroid;
  Eigen::Matrix3d axes;       // columns: principal axes (meshmark::pca, with its sign rule)
  Eigen::Vector3d pa, pb;     // per axis: smallest and largest projection (V_a, V_b)
  Eigen::Vector3i ia, ib;     // the vertices V_a, V_b of each axis (kept fixed by the embedding)
};

// PCA frame of V (MeshError for fewer than 2 vertices or a flat axis).
ChaoFrame chao_frame(const Eigen::Ref<const MatrixX3dR>& V);

// Carrier vertices: every vertex but the (up to 6) extreme vertices, in index order.
VectorXi chao_carriers(Eigen::Index n, const ChaoFrame& f);

// Embed bits (0/1, at most 3 n_layers per carrier vertex) vertex-major: vertex, axis 1..3, layer 1..n_layers.
// Layer j splits [pa, pb] into n_intervals 2^(j-1) intervals with alternating states (index parity);
// a vertex whose interval state differs from its bit is mirrored into the neighbouring interval (layer 1:
// across the nearer boundary; layer j > 1: across the middle of its layer j-1 interval, so that the
// earlier layers keep their bits); it is moved along the axis only.
MatrixX3dR chao_embed(const Eigen::Ref<const MatrixX3dR>& V, const ChaoFrame& f, const VectorXb& bits,
                      int n_layers, int n_intervals);

// Read nbits back in the same order with the frame f (the embedder's, or one computed from the marked mesh).
VectorXb chao_extract(const Eigen::Ref<const MatrixX3dR>& V, const ChaoFrame& f, Eigen::Index nbits,
                      int n_layers, int n_intervals);

}  // namespace meshmark
