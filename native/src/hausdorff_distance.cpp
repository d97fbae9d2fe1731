#include "meshmark/hausdorff_distance.h"
#include "meshmark/error.h"
#include "meshmark/triangle_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <vector>

namespace meshmark {

namespace {
struct Cell {
  Eigen::Vector3d v[3];
  double d[3];
  Index f[3];  // nearest triangle of B to each corner
  double bound;
  bool operator<(const Cell& o) const { return bound < o.bound; }  // max-heap on the bound
};

constexpr double kInf = std::numeric_limits<double>::infinity();

inline double orient2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

// Signed distance of p from the line a->b (> 0 on the left); 0 for a degenerate edge.
inline double side(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const double len = (b - a).norm();
  return len > 0 ? orient2(a, b, p) / len : 0.0;
}

constexpr std::size_t kPatchLimit = 64;  // triangles of B considered by the flat-patch bound

// The flat-patch bound, for a cell lying on a flat part of B: U = the triangles of B near the cell
// (their boxes meet the cell's box) that lie in the plane of the nearest triangle of corner 0. If the
// cell's projection onto that plane lies inside U (every corner in some triangle of U, and no
// boundary edge of U, i.e. an edge not shared by two triangles of U, enters the cell), every point p
// of the cell projects onto B, so d(p, B) <= d(p, plane), whose maximum over the cell is at a corner.
// The tolerance eps (1e-9 of the cell's size: coplanarity, the corner and edge tests) is added to the
// bound. +inf when a test fails. Without it a cell covering several small triangles of a flat region
// (the simplified mesh against its original) is split down to the size of those triangles.
double flat_patch_bound(const Cell& c, const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                        const TriangleTree& tree, std::vector<Index>& S) {
  double diam = 0;
  for (int i = 0; i < 3; ++i) diam = std::max(diam, (c.v[i] - c.v[(i + 1) % 3]).norm());
  const double eps = 1e-9 * diam;
  if (!(eps > 0) || c.f[0] < 0) return kInf;
  const Index t0 = c.f[0];
  const Eigen::Vector3d a0 = V.row(T(t0, 0)).transpose();
  Eigen::Vector3d n = (V.row(T(t0, 1)).transpose() - a0).cross(V.row(T(t0, 2)).transpose() - a0);
  if (!(n.norm() > 0)) return kInf;
  n.normalize();
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min({c.v[0][k], c.v[1][k], c.v[2][k]}) - eps;
    hi[k] = std::max({c.v[0][k], c.v[1][k], c.v[2][k]}) + eps;
  }
  if (!tree.overlapping(lo, hi, S, kPatchLimit)) return kInf;
  auto planar = [&](Index t) {
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(n.dot(V.row(T(t, k)).transpose() - a0)) <= eps)) return false;
    return true;
  };
  S.erase(std::remove_if(S.begin(), S.end(), [&](Index t) { return !planar(t); }), S.end());
  if (S.empty()) return kInf;
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  auto proj = [&](const Eigen::Vector3d& x) { return Eigen::Vector2d((x - a0).dot(u), (x - a0).dot(w)); };
  Eigen::Vector2d p[3];
  for (int i = 0; i < 3; ++i) p[i] = proj(c.v[i]);
  if (orient2(p[0], p[1], p[2]) < 0) std::swap(p[1], p[2]);
  bool in[3] = {false, false, false};
  struct Edge { Index a, b; };
  std::vector<Edge> edges;
  edges.reserve(3 * S.size());
  for (const Index t : S) {
    Eigen::Vector2d q[3];
    for (int k = 0; k < 3; ++k) q[k] = proj(V.row(T(t, k)).transpose());
    if (orient2(q[0], q[1], q[2]) < 0) std::swap(q[1], q[2]);
    const bool area = orient2(q[0], q[1], q[2]) > 0;  // a degenerate triangle contains nothing
    for (int i = 0; i < 3; ++i)
      in[i] = in[i] || (area && side(q[0], q[1], p[i]) >= -eps && side(q[1], q[2], p[i]) >= -eps && side(q[2], q[0], p[i]) >= -eps);
    for (int k = 0; k < 3; ++k) {
      const Index x = T(t, k), y = T(t, (k + 1) % 3);
      edges.push_back({std::min(x, y), std::max(x, y)});
    }
  }
  if (!(in[0] && in[1] && in[2])) return kInf;
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i == 1) {  // a boundary edge of U: clip it by the cell's three half-planes shrunk by eps
      const Eigen::Vector2d e0 = proj(V.row(edges[i].a).transpose()), e1 = proj(V.row(edges[i].b).transpose());
      double s0 = 0, s1 = 1;
      for (int k = 0; k < 3 && s0 < s1; ++k) {
        const double h0 = side(p[k], p[(k + 1) % 3], e0) - eps, h1 = side(p[k], p[(k + 1) % 3], e1) - eps;
        if (h0 <= 0 && h1 <= 0) s1 = -1;
        else if (h0 < 0) s0 = std::max(s0, h0 / (h0 - h1));
        else if (h1 < 0) s1 = std::min(s1, h0 / (h0 - h1));
      }
      if (s0 < s1) return kInf;
    }
    i = j;
  }
  double b = 0;
  for (int i = 0; i < 3; ++i) b = std::max(b, std::abs(n.dot(c.v[i] - a0)));
  return b + 3 * eps;
}

// The split bound for two triangles T1, T2 of B that share an edge e: the plane through e that bisects
// their dihedral angle (normal u1 - u2, u_i the unit direction from e into T_i in its plane) cuts the
// cell into two convex pieces; on the piece on T_i's side d(p, B) <= d(p, T_i), convex, so its maximum
// is at a vertex of the piece (cell corners on that side, and the points where cell edges cross the
// plane). Unlike one triangle for the whole cell, it stays close to d where the cell straddles e
// (coplanar or gently bent neighbours), where the one-triangle bound grows with the cell's size.
// +inf when T1 and T2 share no edge or fold onto each other.
double split_bound(const Cell& c, Index t1, Index t2, const Eigen::Ref<const MatrixX3dR>& V,
                   const Eigen::Ref<const MatrixX3iR>& T, const TriangleTree& tree) {
  int k1 = -1, k2 = -1;  // edge (T1[k1], T1[k1+1]) == edge (T2[k2+1], T2[k2]) or (T2[k2], T2[k2+1])
  for (int i = 0; i < 3 && k1 < 0; ++i)
    for (int j = 0; j < 3; ++j) {
      const Index a = T(t1, i), b = T(t1, (i + 1) % 3), x = T(t2, j), y = T(t2, (j + 1) % 3);
      if ((a == x && b == y) || (a == y && b == x)) {
        k1 = i, k2 = j;
        break;
      }
    }
  if (k1 < 0) return kInf;
  const Eigen::Vector3d a = V.row(T(t1, k1)).transpose(), b = V.row(T(t1, (k1 + 1) % 3)).transpose();
  const Eigen::Vector3d c1 = V.row(T(t1, (k1 + 2) % 3)).transpose(), c2 = V.row(T(t2, (k2 + 2) % 3)).transpose();
  const double len = (b - a).norm();
  if (!(len > 0)) return kInf;
  const Eigen::Vector3d t = (b - a) / len;
  Eigen::Vector3d u1 = (c1 - a) - t.dot(c1 - a) * t, u2 = (c2 - a) - t.dot(c2 - a) * t;
  if (!(u1.norm() > 0) || !(u2.norm() > 0)) return kInf;
  u1.normalize(), u2.normalize();
  Eigen::Vector3d m = u1 - u2;
  if (!(m.norm() > 1e-6)) return kInf;  // folded
  m.normalize();
  double s[3];
  for (int i = 0; i < 3; ++i) s[i] = m.dot(c.v[i] - a);
  double b1 = 0, b2 = 0;  // the bounds of the pieces on T1's (s >= 0) and T2's (s <= 0) side
  for (int i = 0; i < 3; ++i) {
    if (s[i] >= 0) b1 = std::max(b1, tree.face_distance2(t1, c.v[i]));
    if (s[i] <= 0) b2 = std::max(b2, tree.face_distance2(t2, c.v[i]));
    const int j = (i + 1) % 3;
    if ((s[i] < 0 && s[j] > 0) || (s[i] > 0 && s[j] < 0)) {
      const Eigen::Vector3d x = c.v[i] + (s[i] / (s[i] - s[j])) * (c.v[j] - c.v[i]);
      b1 = std::max(b1, tree.face_distance2(t1, x));
      b2 = std::max(b2, tree.face_distance2(t2, x));
    }
  }
  // the crossing point is rounded: the distance is 1-Lipschitz, so allow for its error
  double diam = 0;
  for (int i = 0; i < 3; ++i) diam = std::max(diam, (c.v[i] - c.v[(i + 1) % 3]).norm());
  const double scale = std::max({c.v[0].cwiseAbs().maxCoeff(), c.v[1].cwiseAbs().maxCoeff(), c.v[2].cwiseAbs().maxCoeff()});
  return std::sqrt(std::max(b1, b2)) + 1e-12 * diam + 1e-15 * scale;
}
}  // namespace

HausdorffBound hausdorff_distance(const Eigen::Ref<const MatrixX3dR>& VA, const Eigen::Ref<const MatrixX3iR>& TA,
                                  const Eigen::Ref<const MatrixX3dR>& VB, const Eigen::Ref<const MatrixX3iR>& TB,
                                  double rel_tol, double abs_tol, Eigen::Index max_queries) {
  if (TA.rows() == 0 || TB.rows() == 0) throw MeshError("Hausdorff distance: a mesh has no faces");
  if (!(rel_tol >= 0) || !(abs_tol >= 0)) throw MeshError("Hausdorff distance: tolerances must be >= 0");
  const TriangleTree tree(VB, TB);
  HausdorffBound R;
  auto dist = [&](const Eigen::Vector3d& p, Index* face) {
    ++R.n_queries;
    return std::sqrt(tree.closest(p, face));
  };
  // Exact corner distances, once per referenced vertex.
  std::vector<double> dv(static_cast<size_t>(VA.rows()), -1.0);
  std::vector<Index> fv(static_cast<size_t>(VA.rows()), -1);
  for (Eigen::Index f = 0; f < TA.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index i = TA(f, k);
      if (dv[i] < 0) {
        dv[i] = dist(VA.row(i).transpose(), &fv[i]);
        R.lower = std::max(R.lower, dv[i]);
      }
    }
  std::vector<Index> patch;
  auto threshold = [&]() { return R.lower * (1 + rel_tol) + abs_tol; };
  // Upper bound of d(., B) over a cell: d(p, B) <= d(p, T) for any triangle T of B, and d(., T) is
  // convex, so its maximum over the cell is at a corner: min over candidate T (the nearest triangles
  // of the corners and of the centroid) of max_i d(v_i, T). Also the Lipschitz bounds
  // d(p) <= d(q) + |p - q| with q the centroid or a corner, the flat-patch bound and the split
  // bound of two neighbouring candidates.
  auto bound = [&](Cell& c) {
    const Eigen::Vector3d m = (c.v[0] + c.v[1] + c.v[2]) / 3.0;
    Index fm = -1;
    const double dm = dist(m, &fm);
    R.lower = std::max(R.lower, dm);
    double rc = 0, b = dm;
    for (int i = 0; i < 3; ++i) rc = std::max(rc, (c.v[i] - m).norm());
    b += rc;
    for (int i = 0; i < 3; ++i) {
      double e = 0;
      for (int j = 0; j < 3; ++j) e = std::max(e, (c.v[j] - c.v[i]).norm());
      b = std::min(b, c.d[i] + e);
    }
    Index S[4];
    int ns = 0;
    for (const Index t : {fm, c.f[0], c.f[1], c.f[2]})
      if (t >= 0 && std::find(S, S + ns, t) == S + ns) S[ns++] = t;
    for (int k = 0; k < ns; ++k) {
      double worst = 0;
      for (int i = 0; i < 3 && worst < b * b; ++i) worst = std::max(worst, tree.face_distance2(S[k], c.v[i]));
      b = std::min(b, std::sqrt(worst));
    }
    if (b > threshold() && std::max({c.d[0], c.d[1], c.d[2]}) <= threshold())
      b = std::min(b, flat_patch_bound(c, VB, TB, tree, patch));
    if (b > threshold())
      for (int i = 0; i < ns; ++i)
        for (int j = i + 1; j < ns; ++j) b = std::min(b, split_bound(c, S[i], S[j], VB, TB, tree));
    c.bound = b;
  };
  double dropped = 0;  // the largest bound of a cell left unsplit (it was within the threshold then)
  std::priority_queue<Cell> heap;
  for (Eigen::Index f = 0; f < TA.rows(); ++f) {
    Cell c;
    for (int k = 0; k < 3; ++k) {
      c.v[k] = VA.row(TA(f, k)).transpose();
      c.d[k] = dv[TA(f, k)];
      c.f[k] = fv[TA(f, k)];
    }
    bound(c);
    if (c.bound > threshold()) heap.push(c);
    else dropped = std::max(dropped, c.bound);
  }
  while (!heap.empty()) {
    const Cell c = heap.top();
    if (c.bound <= threshold()) break;
    if (max_queries > 0 && R.n_queries >= max_queries) {
      R.converged = false;
      break;
    }
    heap.pop();
    Eigen::Vector3d m[3];
    double dm[3];
    Index fm[3];
    for (int i = 0; i < 3; ++i) {
      m[i] = 0.5 * (c.v[i] + c.v[(i + 1) % 3]);
      dm[i] = dist(m[i], &fm[i]);
      R.lower = std::max(R.lower, dm[i]);
    }
    // 1-to-4 split: corner cells (v_i, m_i, m_{i-1}) and the middle cell (m_0, m_1, m_2).
    Cell kids[4];
    for (int i = 0; i < 3; ++i) {
      const int p = (i + 2) % 3;
      kids[i].v[0] = c.v[i], kids[i].d[0] = c.d[i], kids[i].f[0] = c.f[i];
      kids[i].v[1] = m[i], kids[i].d[1] = dm[i], kids[i].f[1] = fm[i];
      kids[i].v[2] = m[p], kids[i].d[2] = dm[p], kids[i].f[2] = fm[p];
    }
    for (int i = 0; i < 3; ++i) kids[3].v[i] = m[i], kids[3].d[i] = dm[i], kids[3].f[i] = fm[i];
    for (Cell& k : kids) {
      bound(k);
      // a cell that no longer shrinks (round-off at the scale of its coordinates) is as refined as
      // doubles allow: its bound stays in `dropped` rather than in the heap forever
      if (k.bound > threshold() && !(k.v[0] == c.v[0] && k.v[1] == c.v[1] && k.v[2] == c.v[2])) heap.push(k);
      else dropped = std::max(dropped, k.bound);
    }
  }
  R.upper = std::max({R.lower, dropped, heap.empty() ? 0.0 : heap.top().bound});
  return R;
}

}  // namespace meshmark
