#include "meshmark/nvt36_features.h"
#include "meshmark/edge_faces.h"
#include "meshmark/face_areas.h"
#include "meshmark/face_normals.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/unique_edges.h"
#include "meshmark/unit_cube_normalize.h"
#include "meshmark/vertex_adjacency.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vector>

namespace meshmark {

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();
// log(|d| + floor) for the eigenvalue differences: kFeatureLogFloor = 1e-7, not 2^-52 (docs/steganalysis.md §3:
// the 3x3 solver's own error is ~1e-15; with 2^-52 the log-moments of near-zero eigenvalues varied by 1e-2 under
// rotation, with 1e-12 by up to 2e-6).
constexpr double kLogFloor = kFeatureLogFloor;

// Inverse-distance-weighted 1-ring average (smoothpatch mode 2, one iteration, lambda 1).
MatrixX3dR idw_smooth(const MatrixX3dR& X, const Adjacency& A) {
  MatrixX3dR Y = X;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    Eigen::RowVector3d s = Eigen::RowVector3d::Zero();
    double w = 0;
    for (Offset q = A.ptr[i]; q < A.ptr[i + 1]; ++q) {
      const double d = (X.row(A.nbr[q]) - X.row(i)).norm();
      if (d > 0) s += X.row(A.nbr[q]) / d, w += 1 / d;
    }
    if (w > 0) Y.row(i) = s / w;
  }
  return Y;
}

struct Tensors {  // eigenvalues, descending, of the three tensors; NaN where undefined
  MatrixX3dR face_edge, vertex, face_ring;
};

Eigen::Vector3d eig_desc(const Eigen::Matrix3d& M) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d e = es.eigenvalues();  // ascending
  return Eigen::Vector3d(e[2], e[1], e[0]);
}

Tensors tensors(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T, const EdgeList& edges,
                const EdgeFaces& EF, const VectorXo& vf_ptr, const VectorXi& vf) {
  const Eigen::Index nf = T.rows(), n = X.rows();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const MatrixX3dR N = face_normals(X, T);
  const Eigen::VectorXd area = face_areas(X, T);
  MatrixX3dR C(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) C.row(f) = (X.row(T(f, 0)) + X.row(T(f, 1)) + X.row(T(f, 2))) / 3.0;
  auto nn = [&](Index f) { return Eigen::Matrix3d(N.row(f).transpose() * N.row(f)); };
  Tensors out;
  out.face_edge = MatrixX3dR::Constant(nf, 3, nan);
  // 1. edge-adjacent faces, area weights, normalised (bnvt_feat)
  std::vector<Eigen::Matrix3d> S(nf, Eigen::Matrix3d::Zero());
  std::vector<double> W(nf, 0.0);
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) {
    if (edges.face_count[e] != 2 || EF.f1[e] < 0) continue;
    const Index a = EF.f0[e], b = EF.f1[e];
    S[a] += area[b] * nn(b), W[a] += area[b];
    S[b] += area[a] * nn(a), W[b] += area[a];
  }
  for (Eigen::Index f = 0; f < nf; ++f)
    if (W[f] > 0 && area[f] > 0) out.face_edge.row(f) = eig_desc(S[f] / (W[f] + kEps)).transpose();
  // 2. faces around each vertex, w = area / max area * exp(-3 |c_j - x_i|) (bnvt_feat2)
  out.vertex = MatrixX3dR::Constant(n, 3, nan);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (vf_ptr[i + 1] == vf_ptr[i]) continue;
    double amax = 0;
    for (Offset q = vf_ptr[i]; q < vf_ptr[i + 1]; ++q) amax = std::max(amax, area[vf[q]]);
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (Offset q = vf_ptr[i]; q < vf_ptr[i + 1]; ++q) {
      const Index f = vf[q];
      M += area[f] / (amax + kEps) * std::exp(-3.0 * (C.row(f) - X.row(i)).norm()) * nn(f);
    }
    out.vertex.row(i) = eig_desc(M).transpose();
  }
  // 3. faces sharing a vertex with each face, itself included (bnvt_feat3)
  out.face_ring = MatrixX3dR::Constant(nf, 3, nan);
  std::vector<Index> ring;
  std::vector<Eigen::Index> mark(nf, -1);
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (!(area[f] > 0)) continue;
    ring.clear();
    for (int k = 0; k < 3; ++k)
      for (Offset q = vf_ptr[T(f, k)]; q < vf_ptr[T(f, k) + 1]; ++q)
        if (mark[vf[q]] != f) mark[vf[q]] = f, ring.push_back(vf[q]);
    double amax = 0;
    for (const Index g : ring) amax = std::max(amax, area[g]);
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (const Index g : ring) M += area[g] / (amax + kEps) * std::exp(-3.0 * (C.row(g) - C.row(f)).norm()) * nn(g);
    out.face_ring.row(f) = eig_desc(M).transpose();
  }
  return out;
}
}  // namespace

Eigen::VectorXd nvt36_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  const VectorXb used = feature_mesh_check(V, T);
  const MatrixX3dR X = unit_cube_normalize(V, used);
  const EdgeList edges = unique_edges(n, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(n, edges.E);
  const MatrixX3dR Xs = idw_smooth(X, A);
  const EdgeFaces EF = edge_faces(edges, A, T);
  VectorXo vf_ptr = VectorXo::Zero(n + 1);  // faces around each vertex (CSR)
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++vf_ptr[T(f, k) + 1];
  for (Index i = 0; i < n; ++i) vf_ptr[i + 1] += vf_ptr[i];
  VectorXi vf(vf_ptr[n]);
  VectorXo fill = vf_ptr.head(n);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) vf[fill[T(f, k)]++] = static_cast<Index>(f);
  const Tensors a = tensors(X, T, edges, EF, vf_ptr, vf), b = tensors(Xs, T, edges, EF, vf_ptr, vf);
  Eigen::VectorXd F(kNvt36Size);
  const MatrixX3dR* pa[3] = {&a.face_edge, &a.vertex, &a.face_ring};
  const MatrixX3dR* pb[3] = {&b.face_edge, &b.vertex, &b.face_ring};
  std::vector<double> d;
  for (int t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      d.clear();
      for (Eigen::Index r = 0; r < pa[t]->rows(); ++r) {
        const double x = (*pa[t])(r, k), y = (*pb[t])(r, k);
        if (std::isfinite(x) && std::isfinite(y)) d.push_back(std::abs(x - y));
      }
      F.segment<4>(4 * (3 * t + k)) =
          log_moments(Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size())), -kLogFloor);
    }
  return F;
}

}  // namespace meshmark
