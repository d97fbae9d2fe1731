#include "meshmark/nvt36_features.h"
#include "meshmark/feature_mesh_check.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/pca_min_corner_normalize.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace meshmark {

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();  // MATLAB's eps, 2^-52
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// smoothpatch(fv, 2, 1): Kroon's smoothpatch_inversedistance_double, one iteration, lambda 1, sigma 1.
MatrixX3dR smoothpatch_inverse_distance(const Eigen::Ref<const MatrixX3dR>& X, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index n = X.rows();
  MatrixX3dR N2 = MatrixX3dR::Zero(n, 3);
  Eigen::VectorXd W = Eigen::VectorXd::Zero(n);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Index a = T(f, 0), b = T(f, 1), c = T(f, 2);
    const double w0 = 1 / ((X.row(a) - X.row(b)).norm() + 1.0), w1 = 1 / ((X.row(b) - X.row(c)).norm() + 1.0),
                 w2 = 1 / ((X.row(c) - X.row(a)).norm() + 1.0);
    N2.row(a) += X.row(b) * w0, W[a] += w0;
    N2.row(b) += X.row(a) * w0, W[b] += w0;
    N2.row(b) += X.row(c) * w1, W[b] += w1;
    N2.row(c) += X.row(b) * w1, W[c] += w1;
    N2.row(c) += X.row(a) * w2, W[c] += w2;
    N2.row(a) += X.row(c) * w2, W[a] += w2;
  }
  MatrixX3dR Y(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) Y.row(i) = X.row(i) + (N2.row(i) / W[i] - X.row(i)) * 1.0;  // W = 0: NaN
  return Y;
}

// compute_normal's unit face normals (a norm below eps is taken as 1) and meshSurfaceAreaList's areas.
void normals_and_areas(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T, MatrixX3dR& N, Eigen::VectorXd& area) {
  N.resize(T.rows(), 3);
  area.resize(T.rows());
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d e1 = X.row(T(f, 1)) - X.row(T(f, 0)), e2 = X.row(T(f, 2)) - X.row(T(f, 0));
    const Eigen::Vector3d c = e1.cross(e2);
    double d = c.norm();
    if (d < kEps) d = 1;
    N.row(f) = (c / d).transpose();
    const Eigen::Vector3d n = (e1 / e1.norm()).cross(e2 / e2.norm()), nn = n / n.norm();  // faceNormal, normalised
    const double a = std::abs(c.dot(nn)) / 2;
    area[f] = std::isnan(a) ? 0.0 : a;
  }
}

Eigen::Vector3d eig_desc(const Eigen::Matrix3d& M) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d e = es.eigenvalues();
  return Eigen::Vector3d(e[2], e[1], e[0]);
}

struct Topology {             // what the three tensors need, in the published code's orders
  std::vector<std::vector<Index>> edge_faces;  // trimeshEdgeFaces rows: faces of each unique edge by side position
  std::vector<std::vector<Index>> face_edges;  // bnvt_feat's f_ad: edges with the face in column 1, then column 2
  std::vector<std::vector<Index>> conn;        // neighborelem: faces of each vertex, ascending, once per corner
};

Topology topology(Eigen::Index n, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index nf = T.rows();
  Topology t;
  // sides [1 2], [2 3], [3 1] of every face, position p = block * nf + f; unique sorted pairs (unique 'rows')
  std::vector<std::array<Index, 3>> sides;  // (lo, hi, position)
  sides.reserve(3 * nf);
  const int blk[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  for (int b = 0; b < 3; ++b)
    for (Eigen::Index f = 0; f < nf; ++f) {
      const Index u = T(f, blk[b][0]), v = T(f, blk[b][1]);
      sides.push_back({std::min(u, v), std::max(u, v), static_cast<Index>(b * nf + f)});
    }
  std::sort(sides.begin(), sides.end());
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    std::vector<Index> faces;
    while (j < sides.size() && sides[j][0] == sides[i][0] && sides[j][1] == sides[i][1])
      faces.push_back(static_cast<Index>(sides[j][2] % nf)), ++j;
    t.edge_faces.push_back(std::move(faces));
    i = j;
  }
  t.face_edges.assign(nf, {});
  for (int col = 0; col < 2; ++col)
    for (size_t e = 0; e < t.edge_faces.size(); ++e)
      if (static_cast<int>(t.edge_faces[e].size()) > col) t.face_edges[t.edge_faces[e][col]].push_back(static_cast<Index>(e));
  t.conn.assign(n, {});
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) t.conn[T(f, k)].push_back(static_cast<Index>(f));
  return t;
}

struct Lambdas {
  MatrixX3dR face_edge, vertex, face_ring;  // descending eigenvalues; NaN rows where bnvt_feat gives NaN
};

Lambdas tensors(const MatrixX3dR& X, const Eigen::Ref<const MatrixX3iR>& T, const Topology& topo) {
  const Eigen::Index nf = T.rows(), n = X.rows();
  MatrixX3dR N;
  Eigen::VectorXd area;
  normals_and_areas(X, T, N, area);
  auto nn = [&](Index f) { return Eigen::Matrix3d(N.row(f).transpose() * N.row(f)); };
  MatrixX3dR C(nf, 3);  // tricentroid
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) C(f, k) = 1.0 / 3 * (X(T(f, 0), k) + X(T(f, 1), k) + X(T(f, 2), k));
  Lambdas L;
  L.face_edge = MatrixX3dR::Constant(nf, 3, kNaN);
  for (Eigen::Index k = 0; k < nf; ++k) {  // bnvt_feat
    const auto& fa = topo.face_edges[k];
    if (fa.size() != 3) continue;
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    double w = 0;
    for (const Index e : fa) {
      std::vector<Index> other;  // setdiff(setdiff(row, k), 0)
      for (const Index g : topo.edge_faces[e])
        if (g != k && std::find(other.begin(), other.end(), g) == other.end()) other.push_back(g);
      if (other.size() == 1) S += area[other[0]] * nn(other[0]), w += area[other[0]];
    }
    L.face_edge.row(k) = eig_desc(S / (w + kEps)).transpose();
  }
  auto vote = [&](const std::vector<Index>& ring, const Eigen::RowVector3d& centre) {
    double amax = -std::numeric_limits<double>::infinity();
    for (const Index g : ring) amax = std::max(amax, area[g] + kEps);
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (const Index g : ring) {
      const double t1 = std::exp(-(C.row(g) - centre).norm() / (1.0 / 3));
      M += (area[g] / amax * t1) * nn(g);
    }
    return eig_desc(M);
  };
  L.vertex.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) L.vertex.row(i) = vote(topo.conn[i], X.row(i)).transpose();  // bnvt_feat2
  L.face_ring.resize(nf, 3);
  std::vector<Index> ring;
  for (Eigen::Index f = 0; f < nf; ++f) {  // bnvt_feat3: unique faces sharing a vertex with f
    ring.clear();
    for (int k = 0; k < 3; ++k) ring.insert(ring.end(), topo.conn[T(f, k)].begin(), topo.conn[T(f, k)].end());
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    L.face_ring.row(f) = vote(ring, C.row(f)).transpose();
  }
  return L;
}

// cal_moment: mean, var, skewness, kurtosis of log(x + eps); any NaN makes all four NaN, reported 0.
Eigen::Vector4d cal_moment(const std::vector<double>& x) {
  for (const double v : x)
    if (std::isnan(v)) return Eigen::Vector4d::Zero();
  return log_moments(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())), -kEps);
}
}  // namespace

Eigen::VectorXd nvt36_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  feature_mesh_check(V, T);
  const MatrixX3dR Vs = smoothpatch_inverse_distance(V, T);
  const MatrixX3dR Xo = pca_min_corner_normalize(V), Xs = pca_min_corner_normalize(Vs);
  const Topology topo = topology(V.rows(), T);
  const Lambdas a = tensors(Xo, T, topo), b = tensors(Xs, T, topo);
  const MatrixX3dR* pa[3] = {&a.face_edge, &a.vertex, &a.face_ring};
  const MatrixX3dR* pb[3] = {&b.face_edge, &b.vertex, &b.face_ring};
  Eigen::VectorXd F(kNvt36Size);
  std::vector<double> d;
  for (int t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      d.resize(pa[t]->rows());
      for (Eigen::Index r = 0; r < pa[t]->rows(); ++r) d[r] = std::abs((*pa[t])(r, k) - (*pb[t])(r, k));
      F.segment<4>(4 * (3 * t + k)) = cal_moment(d);
    }
  return F;
}

}  // namespace meshmark
