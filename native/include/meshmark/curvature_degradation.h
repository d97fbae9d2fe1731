// meshmark: degradation of the discrete Gaussian curvature under vertex displacement (thesis §5.2).
#pragma once
#include "meshmark/mesh.h"

#include <cstdint>

namespace meshmark {

enum class Displacement {
  Normal,      // along the vertex normal n_v
  Tangential,  // along a uniformly random unit direction of the tangent plane of n_v
  Random,      // along a uniformly random unit direction of R^3
};

// Vertex normals as in §5.2: the normalized mean of the unit normals of the incident triangles
// (zero-area triangles skipped); (0, 0, 0) where that mean vanishes.
MatrixX3dR mean_face_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

// For each level t[j] and repeat r = 0..repeats-1: every vertex v with moved[v] is displaced by
// s * scale * u_v, s ~ U[-2^(1-t), 2^(1-t)] (so that the mean strength E|s| is 2^-t, §5.2) and u_v the
// unit direction above (vertices with a zero normal are not moved in the Normal and Tangential cases);
// then kappa_dif = mean over the vertices with measured[v] of |kappa'_v - kappa_v| (eq. 5.1.1 through
// the angle sums; the constant 2 pi or pi cancels). Returns (k,) kappa_dif averaged over the repeats.
// Draw order with Rng(seed ^ mix(t, r)): vertex by vertex, s then the direction (tangential: one
// angle; random: 3 normals). MeshError if repeats < 1, scale <= 0, a t is outside 0..1074, the masks
// have the wrong size or no vertex is measured.
Eigen::VectorXd curvature_degradation(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                      const Eigen::Ref<const VectorXi>& t, Displacement direction,
                                      const Eigen::Ref<const VectorXb>& moved, const Eigen::Ref<const VectorXb>& measured,
                                      double scale, int repeats, std::uint64_t seed);

}  // namespace meshmark
