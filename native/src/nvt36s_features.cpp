#include "meshmark/nvt36s_features.h"
#include "meshmark/edge_faces.h"
#include "meshmark/face_areas.h"
#include "meshmark/face_normal_noise.h"
#include "meshmark/face_normals.h"
#include "meshmark/feature_frame.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace meshmark {

namespace {
constexpr double kCap = 0.1;  // an eigenvalue difference whose storage-noise floor exceeds this is left out
const double kNaN = std::numeric_limits<double>::quiet_NaN(), kR3 = std::sqrt(3.0);

// Inverse-distance-weighted 1-ring average (smoothpatch mode 2, one iteration, lambda 1, no sigma: scale-free),
// and the noise multiplier s_i of each smoothed vertex per unit vertex noise:
// 1 + 2 sqrt 3 sum_j |x_j - x_i'| / d_j^2 / sum_j 1 / d_j.
MatrixX3dR idw_smooth(const MatrixX3dR& X, const Adjacency& A, Eigen::VectorXd& s) {
  MatrixX3dR Y = X;
  s = Eigen::VectorXd::Ones(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    Eigen::RowVector3d acc = Eigen::RowVector3d::Zero();
    double w = 0;
    for (Offset q = A.ptr[i]; q < A.ptr[i + 1]; ++q) {
      const double d = (X.row(A.nbr[q]) - X.row(i)).norm();
      if (d > 0) acc += X.row(A.nbr[q]) / d, w += 1 / d;
    }
    if (!(w > 0)) continue;
    Y.row(i) = acc / w;
    double t = 0;
    for (Offset q = A.ptr[i]; q < A.ptr[i + 1]; ++q) {
      const double d = (X.row(A.nbr[q]) - X.row(i)).norm();
      if (d > 0) t += (X.row(A.nbr[q]) - Y.row(i)).norm() / (d * d);
    }
    s[i] = 1 + 2 * kR3 * t / w;
  }
  return Y;
}

struct Tensors {  // descending eigenvalues and their noise bounds; NaN where undefined
  MatrixX3dR lam[3], bnd[3];  // face_edge, vertex, face_ring
};

struct Vote {
  std::vector<Index> g;
  std::vector<double> w, dw;  // weights and bounds of their change
};

// Eigenvalues of sum_g w_g n_g n_g^T (descending) with first-order bounds: for lambda1 Weyl's
// sum (dw_g + 2 w_g min(1, e_g)); for lambda2, lambda3 the same with the component of n_g off the first
// eigenvector (p_g = |(I - v1 v1^T) n_g|): sum (dw_g p_g^2 + 2 w_g p_g e_g + w_g e_g^2), capped by Weyl's.
void eig_bounded(const Vote& v, const MatrixX3dR& N, const Eigen::VectorXd& e, Eigen::Ref<Eigen::RowVector3d> lam,
                 Eigen::Ref<Eigen::RowVector3d> bnd) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < v.g.size(); ++k) M += v.w[k] * (N.row(v.g[k]).transpose() * N.row(v.g[k]));
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M);
  const Eigen::Vector3d ev = es.eigenvalues();
  const Eigen::Vector3d v1 = es.eigenvectors().col(2);
  double b1 = 0, b23 = 0;
  for (size_t k = 0; k < v.g.size(); ++k) {
    const Eigen::Vector3d n = N.row(v.g[k]).transpose();
    const double ek = std::min(1.0, e[v.g[k]]), p = (n - v1 * v1.dot(n)).norm();
    b1 += v.dw[k] + 2 * v.w[k] * ek;
    b23 += v.dw[k] * p * p + 2 * v.w[k] * p * ek + v.w[k] * ek * ek;
  }
  lam << ev[2], ev[1], ev[0];
  bnd << b1, std::min(b1, b23), std::min(b1, b23);
}

Tensors tensors(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T, const EdgeList& edges,
                const EdgeFaces& EF, const VectorXo& vf_ptr, const VectorXi& vf, const Eigen::VectorXd& s) {
  const Eigen::Index nf = T.rows(), n = X.rows();
  const double u = kStorageUnit;
  const MatrixX3dR N = face_normals(X, T);
  const Eigen::VectorXd area = face_areas(X, T), e = u * face_normal_noise(X, T, s);
  Eigen::VectorXd q(nf);  // bound of the change of each area: sqrt 3 s u perimeter
  MatrixX3dR C(nf, 3);
  Eigen::VectorXd sc(nf);  // noise of the centroids
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::RowVector3d a = X.row(T(f, 0)), b = X.row(T(f, 1)), c = X.row(T(f, 2));
    sc[f] = std::max({s[T(f, 0)], s[T(f, 1)], s[T(f, 2)]});
    q[f] = kR3 * sc[f] * u * ((b - a).norm() + (c - b).norm() + (a - c).norm());
    C.row(f) = (a + b + c) / 3.0;
  }
  Tensors out;
  for (int t = 0; t < 3; ++t) {
    const Eigen::Index rows = t == 1 ? n : nf;
    out.lam[t] = MatrixX3dR::Constant(rows, 3, kNaN), out.bnd[t] = out.lam[t];
  }
  // 1. edge-adjacent faces, area weights, normalised (bnvt_feat)
  std::vector<std::vector<Index>> nb(nf);
  for (Eigen::Index k = 0; k < edges.E.rows(); ++k) {
    if (edges.face_count[k] != 2 || EF.f1[k] < 0) continue;
    nb[EF.f0[k]].push_back(EF.f1[k]), nb[EF.f1[k]].push_back(EF.f0[k]);
  }
  Vote v;
  for (Eigen::Index f = 0; f < nf; ++f) {
    double W = 0, Q = 0;
    for (const Index g : nb[f]) W += area[g], Q += q[g];
    if (!(W > 0) || !(area[f] > 0)) continue;
    v.g = nb[f], v.w.clear(), v.dw.clear();
    for (const Index g : nb[f]) v.w.push_back(area[g] / W), v.dw.push_back((q[g] + area[g] / W * Q) / W);
    eig_bounded(v, N, e, out.lam[0].row(f), out.bnd[0].row(f));
  }
  // 2. and 3.: w = area / max area * exp(-3 |c_j - centre|) over the faces around a vertex (bnvt_feat2) or
  // sharing a vertex with a face (bnvt_feat3)
  auto ring_vote = [&](const std::vector<Index>& ring, const Eigen::RowVector3d& centre, double scentre,
                       Eigen::Ref<Eigen::RowVector3d> lam, Eigen::Ref<Eigen::RowVector3d> bnd) {
    double amax = 0, qmax = 0;
    for (const Index g : ring)
      if (area[g] > amax) amax = area[g], qmax = q[g];
    if (!(amax > 0)) return;
    v.g = ring, v.w.clear(), v.dw.clear();
    for (const Index g : ring) {
      const double ex = std::exp(-3.0 * (C.row(g) - centre).norm()), w = area[g] / amax * ex;
      v.w.push_back(w);
      v.dw.push_back(ex * q[g] / amax + w * (qmax / amax + 3 * kR3 * u * (sc[g] + scentre)));
    }
    eig_bounded(v, N, e, lam, bnd);
  };
  std::vector<Index> ring;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (vf_ptr[i + 1] == vf_ptr[i]) continue;
    ring.assign(vf.data() + vf_ptr[i], vf.data() + vf_ptr[i + 1]);
    ring_vote(ring, X.row(i), s[i], out.lam[1].row(i), out.bnd[1].row(i));
  }
  std::vector<Eigen::Index> mark(nf, -1);
  for (Eigen::Index f = 0; f < nf; ++f) {
    if (!(area[f] > 0)) continue;
    ring.clear();
    for (int k = 0; k < 3; ++k)
      for (Offset p = vf_ptr[T(f, k)]; p < vf_ptr[T(f, k) + 1]; ++p)
        if (mark[vf[p]] != f) mark[vf[p]] = f, ring.push_back(vf[p]);
    ring_vote(ring, C.row(f), sc[f], out.lam[2].row(f), out.bnd[2].row(f));
  }
  return out;
}
}  // namespace

Eigen::VectorXd nvt36s_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  const VectorXb used = feature_mesh_check(V, T);
  const FeatureFrame fr = feature_frame(V, used);
  const MatrixX3dR& X = fr.X;
  const EdgeList edges = unique_edges(n, Polygons::from_triangles(T));
  const Adjacency A = vertex_adjacency(n, edges.E);
  Eigen::VectorXd s;
  const MatrixX3dR Xs = idw_smooth(X, A, s);
  const EdgeFaces EF = edge_faces(edges, A, T);
  VectorXo vf_ptr = VectorXo::Zero(n + 1);  // faces around each vertex (CSR)
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++vf_ptr[T(f, k) + 1];
  for (Index i = 0; i < n; ++i) vf_ptr[i + 1] += vf_ptr[i];
  VectorXi vf(vf_ptr[n]);
  VectorXo fill = vf_ptr.head(n);
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) vf[fill[T(f, k)]++] = static_cast<Index>(f);
  const Tensors a = tensors(X, T, edges, EF, vf_ptr, vf, Eigen::VectorXd::Ones(n)), b = tensors(Xs, T, edges, EF, vf_ptr, vf, s);
  Eigen::VectorXd F(kNvt36sSize);
  for (int t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      NoisyVector d;
      d.reserve(a.lam[t].rows());
      for (Eigen::Index r = 0; r < a.lam[t].rows(); ++r) {
        const double x = a.lam[t](r, k), y = b.lam[t](r, k);
        if (std::isfinite(x) && std::isfinite(y)) d.push(std::abs(x - y), a.bnd[t](r, k) + b.bnd[t](r, k));
      }
      F.segment<4>(4 * (3 * t + k)) = floored_log_moments(d, kCap);
    }
  return F;
}

}  // namespace meshmark
