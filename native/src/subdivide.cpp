#include "meshmark/subdivide.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace meshmark {

namespace {

struct SideEdges {
  EdgeList edges;
  std::vector<Index> side;  // (3t) edge id of side k = (corner k, corner k+1) of each triangle
};

SideEdges side_edges(Index n, const Eigen::Ref<const MatrixX3iR>& T) {
  SideEdges s;
  s.edges = unique_edges(n, Polygons::from_triangles(MatrixX3iR(T)));
  const MatrixX2iR& E = s.edges.E;
  std::vector<Offset> first(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index e = 0; e < E.rows(); ++e) ++first[E(e, 0) + 1];
  for (Index i = 0; i < n; ++i) first[i + 1] += first[i];
  s.side.resize(static_cast<size_t>(3 * T.rows()));
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      Index a = T(f, k), b = T(f, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      Offset l = first[a], h = first[a + 1];
      while (l < h) {
        const Offset mid = (l + h) / 2;
        if (E(mid, 1) < b) l = mid + 1; else h = mid;
      }
      s.side[3 * f + k] = static_cast<Index>(l);
    }
  return s;
}

MatrixX3iR split_faces(const Eigen::Ref<const MatrixX3iR>& T, Index n, const std::vector<Index>& side) {
  MatrixX3iR out(4 * T.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Index a = T(f, 0), b = T(f, 1), c = T(f, 2);
    const Index m0 = n + side[3 * f], m1 = n + side[3 * f + 1], m2 = n + side[3 * f + 2];
    out.row(4 * f) << a, m0, m2;
    out.row(4 * f + 1) << b, m1, m0;
    out.row(4 * f + 2) << c, m2, m1;
    out.row(4 * f + 3) << m0, m1, m2;
  }
  return out;
}

}  // namespace

SubdividedMesh midpoint_subdivide(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  const SideEdges s = side_edges(n, T);
  const MatrixX2iR& E = s.edges.E;
  SubdividedMesh out;
  out.V.resize(n + E.rows(), 3);
  out.V.topRows(n) = V;
  for (Eigen::Index e = 0; e < E.rows(); ++e) out.V.row(n + e) = 0.5 * (V.row(E(e, 0)) + V.row(E(e, 1)));
  out.T = split_faces(T, n, s.side);
  return out;
}

SubdividedMesh loop_subdivide(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  const SideEdges s = side_edges(n, T);
  const MatrixX2iR& E = s.edges.E;
  const VectorXi& cnt = s.edges.face_count;
  const Eigen::Index ne = E.rows();
  // edge points: 3/8 (a + b) + 1/8 (c + d) on two-triangle edges, midpoints elsewhere
  MatrixX3dR opp = MatrixX3dR::Zero(ne, 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) opp.row(s.side[3 * f + k]) += V.row(T(f, (k + 2) % 3));
  SubdividedMesh out;
  out.V.resize(n + ne, 3);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const Eigen::RowVector3d ab = V.row(E(e, 0)) + V.row(E(e, 1));
    out.V.row(n + e) = cnt[e] == 2 ? Eigen::RowVector3d(0.375 * ab + 0.125 * opp.row(e)) : Eigen::RowVector3d(0.5 * ab);
  }
  // vertex points
  std::vector<int> valence(static_cast<size_t>(n), 0), nbound(static_cast<size_t>(n), 0);
  std::vector<char> special(static_cast<size_t>(n), 0);
  MatrixX3dR nsum = MatrixX3dR::Zero(n, 3), bsum = MatrixX3dR::Zero(n, 3);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const Index a = E(e, 0), b = E(e, 1);
    ++valence[a];
    ++valence[b];
    nsum.row(a) += V.row(b);
    nsum.row(b) += V.row(a);
    if (cnt[e] != 2) special[a] = special[b] = 1;
    if (cnt[e] == 1) {
      ++nbound[a];
      ++nbound[b];
      bsum.row(a) += V.row(b);
      bsum.row(b) += V.row(a);
    }
  }
  for (Index i = 0; i < n; ++i) {
    if (!special[i] && valence[i] > 0) {
      const double k = valence[i];
      const double c = 0.375 + 0.25 * std::cos(2 * M_PI / k);
      const double beta = (0.625 - c * c) / k;
      out.V.row(i) = (1 - k * beta) * V.row(i) + beta * nsum.row(i);
    } else if (special[i] && nbound[i] == 2) {
      out.V.row(i) = 0.75 * V.row(i) + 0.125 * bsum.row(i);
    } else {
      out.V.row(i) = V.row(i);
    }
  }
  out.T = split_faces(T, n, s.side);
  return out;
}

}  // namespace meshmark
