#include "meshmark/triangle_tree.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace meshmark {

namespace {

// Squared distance from p to triangle (a, a + ab, a + ac): Ericson, Real-Time Collision Detection,
// 5.1.5 (region tests on the barycentric coordinates; exact for degenerate triangles too, which fall
// into the vertex/edge regions).
inline double tri_dist2(const double* p, const double* a, const double* ab, const double* ac) {
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double d1 = ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2];
  const double d2 = ac[0] * ap[0] + ac[1] * ap[1] + ac[2] * ap[2];
  auto sq = [](double x, double y, double z) { return x * x + y * y + z * z; };
  if (d1 <= 0 && d2 <= 0) return sq(ap[0], ap[1], ap[2]);  // vertex a
  const double aa = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  const double abac = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
  const double cc = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
  const double d3 = d1 - aa, d4 = d2 - abac;  // bp = ap - ab
  if (d3 >= 0 && d4 <= d3) return sq(ap[0] - ab[0], ap[1] - ab[1], ap[2] - ab[2]);  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const double v = d1 / (d1 - d3);
    return sq(ap[0] - v * ab[0], ap[1] - v * ab[1], ap[2] - v * ab[2]);
  }
  const double d5 = d1 - abac, d6 = d2 - cc;  // cp = ap - ac
  if (d6 >= 0 && d5 <= d6) return sq(ap[0] - ac[0], ap[1] - ac[1], ap[2] - ac[2]);  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const double w = d2 / (d2 - d6);
    return sq(ap[0] - w * ac[0], ap[1] - w * ac[1], ap[2] - w * ac[2]);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge bc
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    const double q[3] = {ab[0] + w * (ac[0] - ab[0]), ab[1] + w * (ac[1] - ab[1]), ab[2] + w * (ac[2] - ab[2])};
    return sq(ap[0] - q[0], ap[1] - q[1], ap[2] - q[2]);
  }
  const double den = 1.0 / (va + vb + vc);  // inside the face
  const double v = vb * den, w = vc * den;
  return sq(ap[0] - v * ab[0] - w * ac[0], ap[1] - v * ab[1] - w * ac[1], ap[2] - v * ab[2] - w * ac[2]);
}

// The closest point of the same triangle as barycentric weights (u, v, w) of (a, b, c): the same
// region tests as tri_dist2.
inline void tri_closest_bary(const double* p, const double* a, const double* ab, const double* ac, double* bw) {
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double d1 = ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2];
  const double d2 = ac[0] * ap[0] + ac[1] * ap[1] + ac[2] * ap[2];
  auto set = [&](double u, double v, double w) { bw[0] = u, bw[1] = v, bw[2] = w; };
  if (d1 <= 0 && d2 <= 0) return set(1, 0, 0);
  const double aa = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  const double abac = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
  const double cc = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
  const double d3 = d1 - aa, d4 = d2 - abac;
  if (d3 >= 0 && d4 <= d3) return set(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return set(1 - v, v, 0);
  }
  const double d5 = d1 - abac, d6 = d2 - cc;
  if (d6 >= 0 && d5 <= d6) return set(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return set(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return set(0, 1 - w, w);
  }
  const double den = 1.0 / (va + vb + vc);
  const double v = vb * den, w = vc * den;
  set(1 - v - w, v, w);
}

inline double box_dist2(const double* p, const float* lo, const float* hi) {
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = std::max({static_cast<double>(lo[k]) - p[k], 0.0, p[k] - static_cast<double>(hi[k])});
    d += e * e;
  }
  return d;
}

}  // namespace

TriangleTree::TriangleTree(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index t = T.rows();
  if (t == 0) return;
  std::vector<double> cen(static_cast<size_t>(3 * t)), blo(static_cast<size_t>(3 * t)), bhi(static_cast<size_t>(3 * t));
  for (Eigen::Index f = 0; f < t; ++f)
    for (int k = 0; k < 3; ++k) {
      const double a = V(T(f, 0), k), b = V(T(f, 1), k), c = V(T(f, 2), k);
      cen[3 * f + k] = (a + b + c) / 3.0;
      blo[3 * f + k] = std::min({a, b, c});
      bhi[3 * f + k] = std::max({a, b, c});
    }
  std::vector<Index> order(static_cast<size_t>(t));
  std::iota(order.begin(), order.end(), 0);
  nodes_.reserve(static_cast<size_t>(2 * (t / 2 + 1)));
  nodes_.push_back(Node{});
  struct Job { std::int32_t node, first, count; };
  std::vector<Job> jobs{{0, 0, static_cast<std::int32_t>(t)}};
  while (!jobs.empty()) {
    const Job j = jobs.back();
    jobs.pop_back();
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    double clo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, chi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::int32_t i = j.first; i < j.first + j.count; ++i) {
      const Index f = order[i];
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], blo[3 * f + k]);
        hi[k] = std::max(hi[k], bhi[3 * f + k]);
        clo[k] = std::min(clo[k], cen[3 * f + k]);
        chi[k] = std::max(chi[k], cen[3 * f + k]);
      }
    }
    Node& nd = nodes_[j.node];
    for (int k = 0; k < 3; ++k) {  // float box rounded outwards
      nd.lo[k] = std::nextafter(static_cast<float>(lo[k]), -HUGE_VALF);
      nd.hi[k] = std::nextafter(static_cast<float>(hi[k]), HUGE_VALF);
    }
    if (j.count <= 4) {
      nd.left = -1;
      nd.first = j.first;
      nd.count = j.count;
      continue;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    const std::int32_t half = j.count / 2;
    std::nth_element(order.begin() + j.first, order.begin() + j.first + half, order.begin() + j.first + j.count,
                     [&](Index a, Index b) { return cen[3 * a + axis] < cen[3 * b + axis]; });
    const auto left = static_cast<std::int32_t>(nodes_.size());
    nodes_[j.node].left = left;
    nodes_[j.node].count = 0;
    nodes_.push_back(Node{});
    nodes_.push_back(Node{});
    jobs.push_back({left + 1, j.first + half, j.count - half});
    jobs.push_back({left, j.first, half});
  }
  tri_.resize(static_cast<size_t>(t));
  pos_.assign(static_cast<size_t>(t), -1);
  for (Eigen::Index i = 0; i < t; ++i) {
    const Index f = order[i];
    Tri& r = tri_[i];
    for (int k = 0; k < 3; ++k) {
      r.a[k] = V(T(f, 0), k);
      r.ab[k] = V(T(f, 1), k) - r.a[k];
      r.ac[k] = V(T(f, 2), k) - r.a[k];
    }
    r.id = f;
    pos_[f] = static_cast<std::int32_t>(i);
  }
}

MatrixX3dR TriangleTree::face_normals() const {
  MatrixX3dR FN(size(), 3);
  for (const Tri& r : tri_) {
    const Eigen::Vector3d ab(r.ab[0], r.ab[1], r.ab[2]), ac(r.ac[0], r.ac[1], r.ac[2]);
    const Eigen::Vector3d nf = ab.cross(ac);
    const double l = nf.norm();
    FN.row(r.id) = (l > 0 ? Eigen::Vector3d(nf / l) : Eigen::Vector3d::Zero()).transpose();
  }
  return FN;
}

double TriangleTree::face_distance2(Index face, const Eigen::Vector3d& p) const {
  const Tri& r = tri_[pos_[face]];
  const double q[3] = {p[0], p[1], p[2]};
  return tri_dist2(q, r.a, r.ab, r.ac);
}

double TriangleTree::closest_point(const Eigen::Vector3d& p, Index* face, Eigen::Vector3d* q,
                                   Eigen::Vector3d* bary) const {
  Index f = -1;
  const double d2 = closest(p, &f);
  if (face) *face = f;
  if (f < 0) {
    if (q) q->setConstant(std::numeric_limits<double>::quiet_NaN());
    if (bary) bary->setZero();
    return d2;
  }
  const Tri& r = tri_[pos_[f]];
  const double x[3] = {p[0], p[1], p[2]};
  double bw[3];
  tri_closest_bary(x, r.a, r.ab, r.ac, bw);
  if (q)
    for (int k = 0; k < 3; ++k) (*q)[k] = r.a[k] + bw[1] * r.ab[k] + bw[2] * r.ac[k];
  if (bary) *bary = Eigen::Vector3d(bw[0], bw[1], bw[2]);
  return d2;
}

double TriangleTree::closest(const Eigen::Vector3d& p, Index* face) const {
  double best = std::numeric_limits<double>::infinity();
  Index best_id = -1;
  if (nodes_.empty()) {
    if (face) *face = -1;
    return best;
  }
  const double q[3] = {p[0], p[1], p[2]};
  struct Item { std::int32_t node; double d2; };
  Item stack[128];
  int top = 0;
  stack[top++] = {0, box_dist2(q, nodes_[0].lo, nodes_[0].hi)};
  while (top > 0) {
    const Item it = stack[--top];
    if (it.d2 >= best) continue;
    const Node& nd = nodes_[it.node];
    if (nd.left < 0) {
      for (std::int32_t i = nd.first; i < nd.first + nd.count; ++i) {
        const Tri& r = tri_[i];
        const double d = tri_dist2(q, r.a, r.ab, r.ac);
        if (d < best) {
          best = d;
          best_id = r.id;
        }
      }
      continue;
    }
    const Node& L = nodes_[nd.left];
    const Node& R = nodes_[nd.left + 1];
    const double dl = box_dist2(q, L.lo, L.hi), dr = box_dist2(q, R.lo, R.hi);
    // push the farther child first so that the nearer one is visited next
    if (dl <= dr) {
      if (dr < best) stack[top++] = {nd.left + 1, dr};
      if (dl < best) stack[top++] = {nd.left, dl};
    } else {
      if (dl < best) stack[top++] = {nd.left, dl};
      if (dr < best) stack[top++] = {nd.left + 1, dr};
    }
  }
  if (face) *face = best_id;
  return best;
}

bool TriangleTree::overlapping(const double* lo, const double* hi, std::vector<Index>& out, std::size_t limit) const {
  out.clear();
  if (nodes_.empty()) return true;
  auto meets = [&](const float* blo, const float* bhi) {
    for (int k = 0; k < 3; ++k)
      if (static_cast<double>(blo[k]) > hi[k] || static_cast<double>(bhi[k]) < lo[k]) return false;
    return true;
  };
  std::int32_t stack[128];
  int top = 0;
  if (meets(nodes_[0].lo, nodes_[0].hi)) stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (nd.left >= 0) {
      for (const std::int32_t c : {nd.left, nd.left + 1})
        if (meets(nodes_[c].lo, nodes_[c].hi)) stack[top++] = c;
      continue;
    }
    for (std::int32_t i = nd.first; i < nd.first + nd.count; ++i) {
      const Tri& r = tri_[i];
      bool in = true;
      for (int k = 0; k < 3 && in; ++k) {
        const double a = r.a[k], b = a + r.ab[k], c = a + r.ac[k];
        in = std::max({a, b, c}) >= lo[k] && std::min({a, b, c}) <= hi[k];
      }
      if (!in) continue;
      if (out.size() >= limit) return false;
      out.push_back(r.id);
    }
  }
  return true;
}

}  // namespace meshmark
