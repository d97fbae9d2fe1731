#include "meshmark/hausdorff_distance.h"
#include "meshmark/error.h"
#include "meshmark/triangle_tree.h"

#include <algorithm>
#include <cmath>
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
}  // namespace

HausdorffBound hausdorff_distance(const Eigen::Ref<const MatrixX3dR>& VA, const Eigen::Ref<const MatrixX3iR>& TA,
                                  const Eigen::Ref<const MatrixX3dR>& VB, const Eigen::Ref<const MatrixX3iR>& TB,
                                  double rel_tol, double abs_tol) {
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
  // Upper bound of d(., B) over a cell: d(p, B) <= d(p, T) for any triangle T of B, and d(., T) is
  // convex, so its maximum over the cell is at a corner: min over candidate T (the nearest triangles
  // of the corners and of the centroid) of max_i d(v_i, T). Also the Lipschitz bounds
  // d(p) <= d(q) + |p - q| with q the centroid or a corner.
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
    const Index cand[4] = {fm, c.f[0], c.f[1], c.f[2]};
    for (int k = 0; k < 4; ++k) {
      if (cand[k] < 0 || (k > 0 && (cand[k] == cand[0] || (k > 1 && cand[k] == cand[1]) || (k > 2 && cand[k] == cand[2]))))
        continue;
      double worst = 0;
      for (int i = 0; i < 3 && worst < b; ++i) worst = std::max(worst, tree.face_distance2(cand[k], c.v[i]));
      b = std::min(b, std::sqrt(worst));
    }
    c.bound = b;
  };
  std::priority_queue<Cell> heap;
  for (Eigen::Index f = 0; f < TA.rows(); ++f) {
    Cell c;
    for (int k = 0; k < 3; ++k) {
      c.v[k] = VA.row(TA(f, k)).transpose();
      c.d[k] = dv[TA(f, k)];
      c.f[k] = fv[TA(f, k)];
    }
    bound(c);
    if (c.bound > R.lower) heap.push(c);
  }
  R.upper = R.lower;
  while (!heap.empty()) {
    const Cell c = heap.top();
    if (c.bound <= R.lower * (1 + rel_tol) + abs_tol) {
      R.upper = std::max(R.lower, c.bound);
      return R;
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
      if (k.bound > R.lower * (1 + rel_tol) + abs_tol) heap.push(k);
    }
    if (R.n_queries > 200000000) throw MeshError("Hausdorff distance: no convergence (degenerate input?)");
  }
  R.upper = R.lower;
  return R;
}

}  // namespace meshmark
