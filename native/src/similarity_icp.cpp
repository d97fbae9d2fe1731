#include "meshmark/similarity_icp.h"
#include "meshmark/error.h"
#include "meshmark/parallel_for.h"
#include "meshmark/triangle_tree.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <atomic>
#include <cmath>

namespace meshmark {

Similarity umeyama(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& Q, bool with_scale,
                   double fixed_scale) {
  const Eigen::Index n = P.rows();
  if (n == 0 || Q.rows() != n) throw MeshError("umeyama: point sets must be non-empty and of equal size");
  const Eigen::RowVector3d mp = P.colwise().mean(), mq = Q.colwise().mean();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  double varp = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d a = (P.row(i) - mp).transpose(), b = (Q.row(i) - mq).transpose();
    S += b * a.transpose();
    varp += a.squaredNorm();
  }
  S /= static_cast<double>(n);
  varp /= static_cast<double>(n);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d d(1, 1, 1);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) d[2] = -1;  // eq. 43: a rotation
  Similarity r;
  r.R = svd.matrixU() * d.asDiagonal() * svd.matrixV().transpose();
  r.s = with_scale ? (varp > 0 ? svd.singularValues().dot(d) / varp : 1.0) : fixed_scale;  // eq. 42
  r.t = mq.transpose() - r.s * r.R * mp.transpose();                           // eq. 41
  return r;
}

namespace {

struct Step {
  double rms = HUGE_VAL;
  double kept = 0;
};

// One ICP iteration: nearest points of the mapped P, trimming, refit into T (unless refit is false).
// The linearised point-to-plane step with scale (Chen & Medioni 1992; Low 2004, with a scale term):
// minimises sum_i (n_i . (x_i' - q_i))^2 over x' = (1 + sigma)(I + [omega]x)(x - c) + c + tau, with c the
// centroid of the kept x_i; returns the composed similarity.
Similarity plane_update(const Similarity& T, const MatrixX3dR& X, const MatrixX3dR& Q, const MatrixX3dR& N,
                        const std::vector<Eigen::Index>& keep, bool with_scale) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (auto i : keep) c += X.row(i).transpose();
  c /= static_cast<double>(keep.size());
  Eigen::Matrix<double, 7, 7> H = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> g = Eigen::Matrix<double, 7, 1>::Zero();
  for (auto i : keep) {
    const Eigen::Vector3d x = X.row(i).transpose(), n = N.row(i).transpose(), y = x - c;
    Eigen::Matrix<double, 7, 1> J;
    J << y.cross(n), n, with_scale ? n.dot(y) : 0.0;
    const double b = -n.dot(x - Q.row(i).transpose());
    H += J * J.transpose();
    g += J * b;
  }
  const double reg = 1e-9 * H.trace() + 1e-300;
  H.diagonal().array() += reg;
  const Eigen::Matrix<double, 7, 1> xi = H.ldlt().solve(g);
  const Eigen::Vector3d w = xi.head<3>();
  const double ang = w.norm();
  const Eigen::Matrix3d Ru = ang > 0 ? Eigen::AngleAxisd(ang, w / ang).toRotationMatrix() : Eigen::Matrix3d::Identity();
  const double su = with_scale ? std::max(1.0 + xi[6], 0.5) : 1.0;
  Similarity r;
  r.R = Ru * T.R;
  r.s = su * T.s;
  r.t = su * (Ru * (T.t - c)) + c + xi.segment<3>(3);
  return r;
}

Step icp_step(const TriangleTree& tree, const Eigen::Ref<const MatrixX3dR>& P, Similarity& T, double trim,
              bool with_scale, bool refit, MatrixX3dR& X, MatrixX3dR& Q, Eigen::VectorXd& d2, std::vector<double>& tmp,
              const MatrixX3dR* face_normals = nullptr, MatrixX3dR* N = nullptr) {
  const Eigen::Index n = P.rows();
  parallel_for(n, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i) {
      const Eigen::Vector3d x = T.s * (T.R * P.row(i).transpose()) + T.t;
      Index f;
      Eigen::Vector3d q;
      d2[i] = tree.closest_point(x, &f, &q);
      X.row(i) = x.transpose();
      Q.row(i) = q.transpose();
      if (N) N->row(i) = face_normals->row(f);
    }
  }, 1024);
  tmp.assign(d2.data(), d2.data() + n);
  auto quant = [&](double f) {
    const auto k = static_cast<std::ptrdiff_t>(std::clamp<double>(std::floor(f * (n - 1)), 0, n - 1));
    std::nth_element(tmp.begin(), tmp.begin() + k, tmp.end());
    return tmp[k];
  };
  const double q25 = quant(0.25);
  const double qt = quant(trim);
  const double thr = std::min(qt, 16.0 * q25);  // squared: 4 x the 25 % distance
  Eigen::Index m = 0;
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (d2[i] <= thr) ++m, sum += d2[i];
  Step s;
  s.rms = std::sqrt(sum / std::max<Eigen::Index>(m, 1));
  s.kept = static_cast<double>(m) / static_cast<double>(n);
  if (!refit || m < 3) return s;
  if (N) {
    std::vector<Eigen::Index> keep;
    keep.reserve(static_cast<size_t>(m));
    for (Eigen::Index i = 0; i < n; ++i)
      if (d2[i] <= thr) keep.push_back(i);
    T = plane_update(T, X, Q, *N, keep, with_scale);
    return s;
  }
  MatrixX3dR A(m, 3), B(m, 3);
  Eigen::Index k = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (d2[i] <= thr) A.row(k) = P.row(i), B.row(k) = Q.row(i), ++k;
  T = meshmark::umeyama(A, B, with_scale, T.s);
  return s;
}

// Keeps s in [lo, hi] (a point set shrunk onto the surface fits it perfectly: the degenerate minimum of
// point-to-surface ICP with scale), about the centroid-free form: only s changes, t is rescaled with it.
void clamp_scale(Similarity& T, double lo, double hi) {
  T.s = std::clamp(T.s, lo, hi);  // t is refitted by the next step
}

}  // namespace

IcpResult align_similarity(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& V,
                           const Eigen::Ref<const MatrixX3iR>& T, const std::vector<Similarity>& starts,
                           int coarse, int fine, double trim, bool with_scale, double scale_min, double scale_max,
                           int top, int refine) {
  if (T.rows() == 0) throw MeshError("align: the target has no triangles");
  const TriangleTree tree(V, T);
  return align_similarity(P, tree, starts, coarse, fine, trim, with_scale, scale_min, scale_max, top, refine);
}

namespace {

// body(i, X, Q, d2, tmp) for every i in [0, n), spread over the threads by an atomic counter (the
// starts differ in cost: a far start's queries visit more of the tree); each thread has its buffers.
template <class Body>
void for_each_start(size_t count, Eigen::Index n, Body body) {
  std::atomic<size_t> next{0};
  parallel_for(static_cast<std::int64_t>(count), [&](std::int64_t, std::int64_t) {
    MatrixX3dR X(n, 3), Q(n, 3);
    Eigen::VectorXd d2(n);
    std::vector<double> tmp;
    for (size_t i = next++; i < count; i = next++) body(i, X, Q, d2, tmp);
  }, 1);
}

}  // namespace

IcpResult align_similarity(const Eigen::Ref<const MatrixX3dR>& P, const TriangleTree& tree,
                           const std::vector<Similarity>& starts, int coarse, int fine, double trim, bool with_scale,
                           double scale_min, double scale_max, int top, int refine) {
  if (starts.empty()) throw MeshError("align: no start transform");
  if (P.rows() < 3) throw MeshError("align: at least 3 points are needed");
  if (tree.size() == 0) throw MeshError("align: the target has no triangles");
  if (!(trim > 0 && trim <= 1)) throw MeshError("align: trim must be in (0, 1]");
  const Eigen::Index n = P.rows();
  IcpResult best;
  best.rms = HUGE_VAL;
  // Each step scores the transform it starts from and refits; the score of a start is that of its
  // last coarse step. The `top` best starts then run `refine` more steps; the best of them goes on.
  // The starts (and then the refined ones) are independent: one thread each at a time.
  std::vector<std::pair<double, Similarity>> scored(starts.size());
  for_each_start(starts.size(), n, [&](size_t s, MatrixX3dR& X, MatrixX3dR& Q, Eigen::VectorXd& d2,
                                       std::vector<double>& tmp) {
    Similarity cur = starts[s];
    Step st;
    for (int it = 0; it < std::max(coarse, 1); ++it) {
      st = icp_step(tree, P, cur, trim, with_scale, true, X, Q, d2, tmp);
      clamp_scale(cur, scale_min, scale_max);
    }
    scored[s] = {st.rms, cur};
  });
  std::vector<size_t> order(scored.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return scored[a].first < scored[b].first; });
  const size_t n_top = std::min<size_t>(std::max(top, 1), order.size());
  std::vector<std::pair<Step, Similarity>> refined(n_top);
  for_each_start(n_top, n, [&](size_t r, MatrixX3dR& X, MatrixX3dR& Q, Eigen::VectorXd& d2, std::vector<double>& tmp) {
    Similarity cur = scored[order[r]].second;
    Step st;
    st.rms = scored[order[r]].first;
    st.kept = 0;
    for (int it = 0; it < refine; ++it) {
      st = icp_step(tree, P, cur, trim, with_scale, true, X, Q, d2, tmp);
      clamp_scale(cur, scale_min, scale_max);
    }
    refined[r] = {st, cur};
  });
  best.rms = HUGE_VAL;
  for (size_t r = 0; r < n_top; ++r) {
    const Step& st = refined[r].first;
    if (st.rms < best.rms) {
      best.T = refined[r].second;
      best.rms = st.rms;
      best.kept_fraction = st.kept;
      best.start = static_cast<int>(order[r]);
    }
  }
  best.iterations = std::max(coarse, 1) + refine;
  // fine: point-to-plane steps (face normals of the nearest triangles)
  MatrixX3dR X(n, 3), Q(n, 3), N(n, 3);
  Eigen::VectorXd d2(n);
  std::vector<double> tmp;
  const MatrixX3dR FN = fine > 0 ? tree.face_normals() : MatrixX3dR(0, 3);
  Similarity cur = best.T;
  double prev = best.rms;
  for (int it = 0; it < fine; ++it) {
    const Step st = icp_step(tree, P, cur, trim, with_scale, true, X, Q, d2, tmp, &FN, &N);
    clamp_scale(cur, scale_min, scale_max);
    ++best.iterations;
    best.rms = st.rms;
    best.kept_fraction = st.kept;
    if (std::abs(prev - st.rms) <= 1e-9 * prev) break;
    prev = st.rms;
  }
  best.T = cur;
  return best;
}

}  // namespace meshmark
