// meshmark: random re-ordering of vertices and faces (a "distortionless" attack, thesis 6.3.2).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/rng.h"

namespace meshmark {

// Uniform random permutation of 0..n-1 (Fisher-Yates, i from n-1 down to 1 swaps i with rng.below(i+1)).
VectorXi random_permutation(Index n, Rng& rng);

struct PermutedMesh {
  MatrixX3dR V;      // V'[i] = V[vertex_perm[i]]
  Polygons P;        // face j of P' is old face face_perm[j], re-indexed: corner c -> inverse(vertex_perm)[c]
  VectorXi vertex_perm;
  VectorXi face_perm;
};

// Draw order with Rng(seed): the vertex permutation (if permute_vertices), then the face
// permutation (if permute_faces). Corner order inside a face is kept (orientation preserved).
PermutedMesh permute_mesh(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P, std::uint64_t seed,
                          bool permute_vertices = true, bool permute_faces = true);

}  // namespace meshmark
