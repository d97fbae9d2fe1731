#include "meshmark/vertex_adjacency.h"

#include <algorithm>

namespace meshmark {

Adjacency vertex_adjacency(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E) {
  Adjacency A;
  A.ptr = VectorXo::Zero(n_vertices + 1);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    ++A.ptr[E(e, 0) + 1];
    ++A.ptr[E(e, 1) + 1];
  }
  for (Index i = 0; i < n_vertices; ++i) A.ptr[i + 1] += A.ptr[i];
  A.nbr.resize(A.ptr[n_vertices]);
  VectorXo fill = A.ptr.head(n_vertices);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    A.nbr[fill[E(e, 0)]++] = E(e, 1);
    A.nbr[fill[E(e, 1)]++] = E(e, 0);
  }
  for (Index i = 0; i < n_vertices; ++i) std::sort(A.nbr.data() + A.ptr[i], A.nbr.data() + A.ptr[i + 1]);
  return A;
}

VectorXi valence(Index n_vertices, const Eigen::Ref<const MatrixX2iR>& E) {
  VectorXi d = VectorXi::Zero(n_vertices);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    ++d[E(e, 0)];
    ++d[E(e, 1)];
  }
  return d;
}

}  // namespace meshmark
