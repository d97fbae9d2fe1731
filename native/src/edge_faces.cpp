#include "meshmark/edge_faces.h"

#include <utility>

namespace meshmark {

EdgeFaces edge_faces(const EdgeList& edges, const Adjacency& A, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index ne = edges.E.rows(), n = A.ptr.size() - 1;
  // first[a]: index of the first edge (a, .) in the lexicographically sorted edge list
  VectorXo first = VectorXo::Zero(n + 1);
  for (Eigen::Index e = 0; e < ne; ++e) ++first[edges.E(e, 0) + 1];
  for (Eigen::Index i = 0; i < n; ++i) first[i + 1] += first[i];
  EdgeFaces out;
  out.f0 = VectorXi::Constant(ne, -1);
  out.f1 = VectorXi::Constant(ne, -1);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      Index a = T(f, k), b = T(f, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      Offset e = first[a];  // rank of b among the neighbours of a larger than a
      for (Offset q = A.ptr[a]; q < A.ptr[a + 1] && A.nbr[q] < b; ++q)
        if (A.nbr[q] > a) ++e;
      (out.f0[e] < 0 ? out.f0[e] : out.f1[e]) = static_cast<Index>(f);
    }
  return out;
}

}  // namespace meshmark
