// C++ tests of the triangulation of large polygons (ear_clip_polygon and triangulate's dispatch):
// counts, corners, and validity checked independently of the clipper (the triangles' boundary chain
// equals the polygon's and every triangle turns left, which together mean they tile the polygon).
#include "meshmark/ear_clip_polygon.h"
#include "meshmark/triangulate.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

using namespace meshmark;

namespace {

using Pts = std::vector<Eigen::Vector2d>;

long double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (static_cast<long double>(b.x()) - a.x()) * (static_cast<long double>(c.y()) - a.y()) -
         (static_cast<long double>(b.y()) - a.y()) * (static_cast<long double>(c.x()) - a.x());
}

long double shoelace(const Pts& q) {
  long double s = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    const auto& a = q[i];
    const auto& b = q[(i + 1) % q.size()];
    s += static_cast<long double>(a.x()) * b.y() - static_cast<long double>(b.x()) * a.y();
  }
  return s / 2;
}

// n - 2 triangles over corners 0..n-1, every corner used.
void expect_complete(const std::vector<int>& tri, int n) {
  ASSERT_EQ(tri.size(), 3u * static_cast<size_t>(n - 2));
  std::vector<char> used(static_cast<size_t>(n), 0);
  for (int c : tri) {
    ASSERT_GE(c, 0);
    ASSERT_LT(c, n);
    used[static_cast<size_t>(c)] = 1;
  }
  for (int i = 0; i < n; ++i) EXPECT_TRUE(used[static_cast<size_t>(i)]) << "corner " << i << " unused";
}

// The boundary of the triangles (directed edges, opposite ones cancelling) is the polygon's
// boundary, and no triangle turns right: then the triangles cover the polygon exactly once.
void expect_tiling(const Pts& q, const std::vector<int>& tri) {
  std::map<std::pair<int, int>, int> chain;
  auto add = [&](int u, int v, int s) {
    if (u < v) chain[{u, v}] += s;
    else chain[{v, u}] -= s;
  };
  const int n = static_cast<int>(q.size());
  for (int i = 0; i < n; ++i) add(i, (i + 1) % n, -1);
  long double area = 0;
  int right_turns = 0;
  for (size_t t = 0; t < tri.size(); t += 3) {
    for (int e = 0; e < 3; ++e) add(tri[t + e], tri[t + (e + 1) % 3], 1);
    const long double o = orient(q[tri[t]], q[tri[t + 1]], q[tri[t + 2]]);
    if (o < 0) ++right_turns;
    area += o / 2;
  }
  int open = 0;
  for (const auto& [edge, count] : chain) open += count != 0;
  EXPECT_EQ(open, 0) << "edges left over in the boundary chain";
  EXPECT_EQ(right_turns, 0);
  EXPECT_NEAR(static_cast<double>(area), static_cast<double>(shoelace(q)), 1e-9 * std::fabs(static_cast<double>(shoelace(q))));
}

// A star: radii alternating between an outer (jittered) and an inner ring, counter-clockwise.
Pts star(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(0.0, 0.3);
  Pts q(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n, r = (i % 2 ? 0.5 : 1.0) + jitter(rng);
    q[static_cast<size_t>(i)] = {r * std::cos(t), r * std::sin(t)};
  }
  return q;
}

}  // namespace

TEST(EarClipPolygon, StarOf20000CornersIsTiled) {
  const Pts q = star(20000, 7);
  std::vector<int> tri;
  const EarClipReport rep = ear_clip_polygon(q, tri);
  expect_complete(tri, 20000);
  expect_tiling(q, tri);
  EXPECT_EQ(rep.fans, 0);
  EXPECT_EQ(rep.splits, 0);
  EXPECT_LT(rep.work, 1000LL * 20000);  // the grid keeps each test local (about 60 per corner)
}

TEST(EarClipPolygon, CombWithCollinearRunsIsTiled) {
  // A comb: 200 teeth of height 10 on a base, every edge subdivided into collinear corners.
  Pts outline;
  for (int t = 0; t < 200; ++t) {
    outline.push_back({2.0 * t, 0.0});
    outline.push_back({2.0 * t, 10.0});
    outline.push_back({2.0 * t + 1, 10.0});
    outline.push_back({2.0 * t + 1, 0.0});
  }
  outline.push_back({400, 0});
  outline.push_back({400, -1});
  outline.push_back({0, -1});
  // clockwise as built (teeth go up while x grows along the top): reverse to counter-clockwise
  std::reverse(outline.begin(), outline.end());
  Pts q;
  for (size_t i = 0; i < outline.size(); ++i) {
    const auto& a = outline[i];
    const auto& b = outline[(i + 1) % outline.size()];
    for (int s = 0; s < 4; ++s) q.push_back(a + (b - a) * (s / 4.0));
  }
  ASSERT_GT(shoelace(q), 0);
  std::vector<int> tri;
  ear_clip_polygon(q, tri);
  expect_complete(tri, static_cast<int>(q.size()));
  expect_tiling(q, tri);
}

TEST(EarClipPolygon, SpiralIsTiled) {
  // A thick spiral strip: the outer edge out, the inner edge back (very concave, long thin ears).
  const int k = 3000;
  Pts q;
  for (int i = 0; i < k; ++i) {
    const double t = 8 * M_PI * i / k;
    q.push_back({(1 + t) * std::cos(t), (1 + t) * std::sin(t)});
  }
  for (int i = k - 1; i >= 0; --i) {
    const double t = 8 * M_PI * i / k;
    q.push_back({(1.5 + t) * std::cos(t), (1.5 + t) * std::sin(t)});
  }
  if (shoelace(q) < 0) std::reverse(q.begin(), q.end());
  std::vector<int> tri;
  ear_clip_polygon(q, tri);
  expect_complete(tri, static_cast<int>(q.size()));
  expect_tiling(q, tri);
}

TEST(EarClipPolygon, SelfIntersectingAndDegenerateInputTerminateComplete) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  // random corners: a polygon that crosses itself everywhere
  Pts random(20000);
  for (auto& p : random) p = {u(rng), u(rng)};
  // a nearly flat zig-zag (amplitude 1e-13 on a unit length) and a polygon of one repeated point
  Pts flat(5000), point(500, Eigen::Vector2d(0.25, 0.25));
  for (int i = 0; i < 5000; ++i) flat[static_cast<size_t>(i)] = {i < 2500 ? i / 2500.0 : (5000 - i) / 2500.0,
                                                                  (i % 2 ? 1e-13 : 0) + (i < 2500 ? 0 : 1e-12)};
  // a pinched polygon: two squares meeting at one corner, as one ring through the shared point twice
  Pts pinch{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}};
  for (const Pts* q : {&random, &flat, &point, &pinch}) {
    std::vector<int> tri;
    ear_clip_polygon(*q, tri);
    expect_complete(tri, static_cast<int>(q->size()));
  }
  std::vector<int> tri;
  ear_clip_polygon(pinch, tri);
  expect_tiling(pinch, tri);
}

TEST(EarClipPolygon, WorkLimitEndsInAFan) {
  const Pts q = star(5000, 1);
  std::vector<int> tri;
  const EarClipReport rep = ear_clip_polygon(q, tri, 1000);
  expect_complete(tri, 5000);
  EXPECT_EQ(rep.fans, 1);
  EXPECT_LT(rep.work, 1000 + 5000 + 100);  // stops at the first check past the limit (plus the index)
}

TEST(Triangulate, LargeConvexPolygonIsTheFanAndLargeStarIsTiledInItsPlane) {
  const int n = 1000;
  // a regular 1000-gon in the plane x + y + z = 0 far from the origin, then a star in the same plane
  const Eigen::Vector3d e1 = Eigen::Vector3d(1, -1, 0).normalized(), e2 = Eigen::Vector3d(1, 1, -2).normalized();
  const Eigen::Vector3d far(1e4, 2e4, -3e4);
  const Pts s = star(n, 11);
  MatrixX3dR V(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    V.row(i) = (far + std::cos(t) * e1 + std::sin(t) * e2).transpose();
    V.row(n + i) = (far + s[static_cast<size_t>(i)].x() * e1 + s[static_cast<size_t>(i)].y() * e2).transpose();
  }
  Polygons P;
  P.indices.resize(2 * n);
  for (int i = 0; i < 2 * n; ++i) P.indices[i] = i;
  P.offsets.resize(3);
  P.offsets << 0, n, 2 * n;
  const Triangulation T = triangulate(V, P);
  ASSERT_EQ(T.T.rows(), 2 * (n - 2));
  for (int t = 0; t < n - 2; ++t) {
    EXPECT_EQ(T.T(t, 0), 0);
    EXPECT_EQ(T.T(t, 1), t + 1);
    EXPECT_EQ(T.T(t, 2), t + 2);
    EXPECT_EQ(T.face[t], 0);
  }
  std::vector<int> tri;
  for (int t = n - 2; t < 2 * (n - 2); ++t) {
    EXPECT_EQ(T.face[t], 1);
    for (int c = 0; c < 3; ++c) tri.push_back(T.T(t, c) - n);
  }
  expect_complete(tri, n);
  expect_tiling(s, tri);  // the winding of e1 x e2 is the plane's Newell normal: same orientation
}

TEST(Triangulate, NonPlanarLargePolygonIsTiledInItsNewellPlane) {
  // a star on a saddle z = 0.1 (x^2 - y^2) (gentle enough for its projection to stay simple):
  // clipped in the plane of its Newell normal
  const int n = 1000;
  const Pts s = star(n, 5);
  MatrixX3dR V(n, 3);
  for (int i = 0; i < n; ++i) {
    const auto& p = s[static_cast<size_t>(i)];
    V.row(i) << p.x(), p.y(), 0.1 * (p.x() * p.x() - p.y() * p.y());
  }
  Polygons P;
  P.indices.resize(n);
  for (int i = 0; i < n; ++i) P.indices[i] = i;
  P.offsets.resize(2);
  P.offsets << 0, n;
  const Triangulation T = triangulate(V, P);
  std::vector<int> tri(T.T.data(), T.T.data() + T.T.size());
  expect_complete(tri, n);
  // the projection to the Newell plane (any in-plane frame: tiling does not depend on it)
  Eigen::Vector3d nrm = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) nrm += V.row(i).transpose().cross(V.row((i + 1) % n).transpose());
  nrm.normalize();
  const Eigen::Vector3d u = nrm.cross(Eigen::Vector3d::UnitY()).normalized(), w = nrm.cross(u);
  Pts q(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) q[static_cast<size_t>(i)] = {V.row(i).dot(u.transpose()), V.row(i).dot(w.transpose())};
  EXPECT_GT(nrm.z(), 0.999);
  expect_tiling(q, tri);
  std::vector<int> direct;
  const EarClipReport rep = ear_clip_polygon(q, direct);
  EXPECT_EQ(rep.fans, 0);
  EXPECT_EQ(rep.splits, 0);
  EXPECT_EQ(rep.cured, 0);
  EXPECT_GT(shoelace(q), 0);
  expect_tiling(q, direct);
}
