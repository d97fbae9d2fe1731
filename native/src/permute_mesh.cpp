#include "meshmark/permute_mesh.h"

#include <utility>

namespace meshmark {

VectorXi random_permutation(Index n, Rng& rng) {
  VectorXi p(n);
  for (Index i = 0; i < n; ++i) p[i] = i;
  for (Index i = n - 1; i > 0; --i) std::swap(p[i], p[static_cast<Index>(rng.below(static_cast<std::uint64_t>(i) + 1))]);
  return p;
}

PermutedMesh permute_mesh(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P, std::uint64_t seed,
                          bool permute_vertices, bool permute_faces) {
  Rng rng(seed);
  const Index n = static_cast<Index>(V.rows());
  const Index m = static_cast<Index>(P.n_faces());
  PermutedMesh out;
  if (permute_vertices) {
    out.vertex_perm = random_permutation(n, rng);
  } else {
    out.vertex_perm.resize(n);
    for (Index i = 0; i < n; ++i) out.vertex_perm[i] = i;
  }
  if (permute_faces) {
    out.face_perm = random_permutation(m, rng);
  } else {
    out.face_perm.resize(m);
    for (Index i = 0; i < m; ++i) out.face_perm[i] = i;
  }
  VectorXi inv(n);
  out.V.resize(n, 3);
  for (Index i = 0; i < n; ++i) {
    inv[out.vertex_perm[i]] = i;
    out.V.row(i) = V.row(out.vertex_perm[i]);
  }
  out.P.indices.resize(P.n_corners());
  out.P.offsets.resize(m + 1);
  out.P.offsets[0] = 0;
  Offset c = 0;
  for (Index j = 0; j < m; ++j) {
    const Index f = out.face_perm[j];
    for (Offset k = P.offsets[f]; k < P.offsets[f + 1]; ++k) out.P.indices[c++] = inv[P.indices[k]];
    out.P.offsets[j + 1] = c;
  }
  return out;
}

}  // namespace meshmark
