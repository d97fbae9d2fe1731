// meshmark: additive noise attacks (thesis eq. 6.3.12 and variants).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

enum class NoiseKind {
  Uniform,   // x_i' = x_i + a_i d,  a_i ~ U[-A, A] per coordinate                      (eq. 6.3.12)
  Gaussian,  // x_i' = x_i + a_i d,  a_i ~ N(0, A^2) per coordinate
  Normal,    // v_i' = v_i + a_i d n_i,  a_i ~ U[-A, A] once per vertex, n_i the unit vertex normal
  Tangent,   // v_i' = v_i + A d (u_i - (u_i . n_i) n_i),  u_i ~ U[-1, 1]^3 (tangent plane only)
};

// A: strength as a fraction (A = 0.0025 is the thesis' 0.25 %); d = mean_centroid_distance of the
// vertices referenced by T (eq. 6.3.12's "average distance from vertices to object center").
// Unreferenced vertices are not moved. Normal/Tangent: vertices with a zero normal are not moved.
// Draw order with Rng(seed): vertex by vertex in index order (unreferenced ones included, so the
// stream does not depend on the faces): Uniform/Tangent 3 x uniform(-1,1) (x, y, z), Gaussian
// 3 x normal(), Normal 1 x uniform(-1,1). MeshError if A < 0 or not finite.
MatrixX3dR add_noise(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T, NoiseKind kind,
                     double A, std::uint64_t seed);

}  // namespace meshmark
