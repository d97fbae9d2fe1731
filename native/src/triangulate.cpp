#include "meshmark/triangulate.h"
#include "meshmark/ear_clip_polygon.h"

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

namespace meshmark {

namespace {

// 2D cross product sign of (b-a) x (c-a).
inline double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

bool inside_triangle(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                     const Eigen::Vector2d& c) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

// Ear clipping of polygon `poly` (vertex ids) projected to 2D points `q` (counter-clockwise
// with respect to the Newell normal). Appends triangles; returns false when no ear exists.
bool ear_clip(std::vector<Index> poly, std::vector<Eigen::Vector2d> q, std::vector<Index>& tri) {
  while (poly.size() > 3) {
    const size_t k = poly.size();
    bool clipped = false;
    for (size_t j = 1; j <= k && !clipped; ++j) {  // start at corner 1: convex polygons give the fan from 0
      const size_t i = j % k, p = (i + k - 1) % k, n = (i + 1) % k;
      if (orient(q[p], q[i], q[n]) <= 0) continue;  // reflex or flat corner
      bool empty = true;
      for (size_t r = 0; r < k && empty; ++r) {
        if (r == p || r == i || r == n) continue;
        if (inside_triangle(q[r], q[p], q[i], q[n])) empty = false;
      }
      if (!empty) continue;
      tri.insert(tri.end(), {poly[p], poly[i], poly[n]});
      poly.erase(poly.begin() + static_cast<long>(i));
      q.erase(q.begin() + static_cast<long>(i));
      clipped = true;
    }
    if (!clipped) return false;
  }
  tri.insert(tri.end(), {poly[0], poly[1], poly[2]});
  return true;
}

// Polygons with more corners than this go to ear_clip_polygon (grid index, about O(k log k));
// up to it the scan above (O(k^2) to O(k^3)) is kept, so small polygons triangulate as they always did.
constexpr Index kScanMaxCorners = 64;

// Strictly convex: every corner turns left and the turns add up to one full turn (not two or more).
bool strictly_convex(const std::vector<Eigen::Vector2d>& q) {
  const size_t k = q.size();
  double turning = 0;
  for (size_t i = 0; i < k; ++i) {
    const Eigen::Vector2d& a = q[(i + k - 1) % k];
    const Eigen::Vector2d& b = q[i];
    const Eigen::Vector2d& c = q[(i + 1) % k];
    const double cross = orient(a, b, c);
    if (!(cross > 0)) return false;
    turning += std::atan2(cross, (b - a).dot(c - b));
  }
  return turning < 3 * M_PI;
}

}  // namespace

Triangulation triangulate(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P) {
  const Offset m = P.n_faces();
  std::vector<Index> tri, src;
  tri.reserve(static_cast<size_t>(3 * (P.n_corners() - 2 * m)));
  std::vector<Index> poly, local;
  std::vector<Eigen::Vector2d> q;
  for (Offset f = 0; f < m; ++f) {
    const Offset b = P.offsets[f];
    const Index k = P.face_size(f);
    const size_t before = tri.size();
    if (k == 3) {
      tri.insert(tri.end(), {P.indices[b], P.indices[b + 1], P.indices[b + 2]});
    } else {
      // Newell normal and an orthonormal frame of the polygon's plane. Large polygons are taken
      // relative to corner 0, so that a far-off polygon keeps its digits in the orientation tests.
      const bool large = k > kScanMaxCorners;
      const Eigen::Vector3d origin = large ? Eigen::Vector3d(V.row(P.indices[b]).transpose()) : Eigen::Vector3d::Zero();
      Eigen::Vector3d nrm = Eigen::Vector3d::Zero();
      for (Index j = 0; j < k; ++j) {
        const Eigen::Vector3d a = V.row(P.indices[b + j]).transpose() - origin;
        const Eigen::Vector3d c = V.row(P.indices[b + (j + 1) % k]).transpose() - origin;
        nrm += a.cross(c);
      }
      poly.assign(P.indices.data() + b, P.indices.data() + b + k);
      bool done = false;
      if (nrm.norm() > 0) {
        nrm.normalize();
        Eigen::Vector3d u = nrm.unitOrthogonal(), w = nrm.cross(u);
        q.resize(k);
        for (Index j = 0; j < k; ++j) {
          const Eigen::Vector3d p = V.row(poly[j]).transpose() - origin;
          q[j] = Eigen::Vector2d(p.dot(u), p.dot(w));
        }
        if (!large) {
          done = ear_clip(poly, q, tri);
          if (!done) tri.resize(before);
        } else if (!strictly_convex(q)) {  // a convex polygon is the fan below, as the scan gives it
          local.clear();
          ear_clip_polygon(q, local);
          for (Index c : local) tri.push_back(poly[c]);
          done = true;
        }
      }
      if (!done)  // degenerate polygon: fan from corner 0
        for (Index j = 1; j + 1 < k; ++j) tri.insert(tri.end(), {poly[0], poly[j], poly[j + 1]});
    }
    src.insert(src.end(), (tri.size() - before) / 3, static_cast<Index>(f));
  }
  Triangulation out;
  out.T = Eigen::Map<MatrixX3iR>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  out.face = Eigen::Map<VectorXi>(src.data(), static_cast<Eigen::Index>(src.size()));
  return out;
}

}  // namespace meshmark
