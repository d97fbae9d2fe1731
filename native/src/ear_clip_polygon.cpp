// Ear clipping with a spatial index of the corners, in the spirit of mapbox/earcut (V. Agafonkin),
// whose z-order index looks at every corner in an ear's bounding box. The long thin ears of a deep
// star have boxes holding a fraction of all corners (quadratic time: 10 s for 100,000 corners), so
// here the corners sit in a uniform grid of about one corner per cell and a test visits only the cells
// that the triangle itself crosses, row by row. Every stall handler emits the triangles of the
// corners it removes, so the output always has n - 2 triangles over all n corners; total work is capped.
#include "meshmark/ear_clip_polygon.h"

#include <algorithm>
#include <cmath>

namespace meshmark {

namespace {

struct Node {
  double x, y;
  int corner;                  // position in the input polygon
  int prev, next;              // ring
  int prev_z = -1, next_z = -1;  // list of the grid cell holding the corner (ring being clipped)
  int z = 0;                     // that cell
};

class Clipper {
 public:
  Clipper(const std::vector<Eigen::Vector2d>& q, std::vector<int>& tri, long long limit) : tri_(tri), limit_(limit) {
    const int n = static_cast<int>(q.size());
    nodes_.reserve(static_cast<size_t>(n) + 64);
    for (int i = 0; i < n; ++i) nodes_.push_back(Node{q[i].x(), q[i].y(), i, (i + n - 1) % n, (i + 1) % n});
    if (limit_ < 0) limit_ = 20000000LL + 300LL * n * static_cast<long long>(std::ceil(std::log2(n + 1.0)));
  }

  EarClipReport run() {
    // Ring (start node, size) still to do. Start at corner 1, as triangulate's small-polygon scan.
    std::vector<std::pair<int, int>> todo{{1 % static_cast<int>(nodes_.size()), static_cast<int>(nodes_.size())}};
    while (!todo.empty()) {
      const auto [start, m] = todo.back();
      todo.pop_back();
      clip_ring(start, m, todo);
    }
    return report_;
  }

 private:
  std::vector<Node> nodes_;
  std::vector<int>& tri_;
  long long limit_;
  double gx_ = 0, gy_ = 0, cw_ = 1, ch_ = 1;  // grid origin and cell size
  int gw_ = 1, gh_ = 1;                       // grid columns and rows
  std::vector<int> cells_;                    // first corner of each cell
  EarClipReport report_;

  Node& at(int i) { return nodes_[static_cast<size_t>(i)]; }

  // > 0: a, b, c turn left (counter-clockwise); the sign convention of triangulate.cpp.
  double orient(int a, int b, int c) {
    const Node &A = at(a), &B = at(b), &C = at(c);
    return (B.x - A.x) * (C.y - A.y) - (B.y - A.y) * (C.x - A.x);
  }
  bool same_point(int a, int b) { return at(a).x == at(b).x && at(a).y == at(b).y; }

  int col(double x) const { return std::min(gw_ - 1, std::max(0, static_cast<int>((x - gx_) / cw_))); }
  int row(double y) const { return std::min(gh_ - 1, std::max(0, static_cast<int>((y - gy_) / ch_))); }

  void emit(int a, int b, int c) { tri_.insert(tri_.end(), {at(a).corner, at(b).corner, at(c).corner}); }

  void unlink(int p) {
    Node& P = at(p);
    at(P.prev).next = P.next;
    at(P.next).prev = P.prev;
    if (P.prev_z >= 0) at(P.prev_z).next_z = P.next_z;
    else cells_[static_cast<size_t>(P.z)] = P.next_z;
    if (P.next_z >= 0) at(P.next_z).prev_z = P.prev_z;
  }

  // The ring's nodes into a grid over the ring's bounding box, about one per cell.
  void index_ring(int start, int m) {
    double hx = at(start).x, hy = at(start).y;
    gx_ = hx;
    gy_ = hy;
    int p = start;
    for (int i = 0; i < m; ++i, p = at(p).next) {
      gx_ = std::min(gx_, at(p).x), gy_ = std::min(gy_, at(p).y);
      hx = std::max(hx, at(p).x), hy = std::max(hy, at(p).y);
    }
    const double w = hx - gx_, h = hy - gy_;
    if (w > 0 && h > 0) {
      gw_ = std::max(1, std::min(m, static_cast<int>(std::sqrt(m * w / h))));
      gh_ = std::max(1, std::min(m / gw_, static_cast<int>(std::sqrt(m * h / w))));
    } else {
      gw_ = w > 0 ? m : 1;
      gh_ = h > 0 ? m : 1;
    }
    cw_ = w > 0 ? w / gw_ : 1.0;
    ch_ = h > 0 ? h / gh_ : 1.0;
    cells_.assign(static_cast<size_t>(gw_) * static_cast<size_t>(gh_), -1);
    for (int i = 0; i < m; ++i, p = at(p).next) {  // inserted in ring order: deterministic
      Node& P = at(p);
      P.z = row(P.y) * gw_ + col(P.x);
      P.prev_z = -1;
      P.next_z = cells_[static_cast<size_t>(P.z)];
      if (P.next_z >= 0) at(P.next_z).prev_z = p;
      cells_[static_cast<size_t>(P.z)] = p;
    }
    report_.work += m;
  }

  // x-range of the segment p-q within the band y0 <= y <= y1 (widened into lo, hi).
  void clip_x(int p, int q, double y0, double y1, double& lo, double& hi) {
    double x0 = at(p).x, ya = at(p).y, x1 = at(q).x, yb = at(q).y;
    if (std::max(ya, yb) < y0 || std::min(ya, yb) > y1) return;
    if (ya != yb) {
      auto x_at = [&](double y) { return x0 + (x1 - x0) * ((y - ya) / (yb - ya)); };
      const double ylo = std::max(std::min(ya, yb), y0), yhi = std::min(std::max(ya, yb), y1);
      const double xa = x_at(ylo), xb = x_at(yhi);
      x0 = xa;
      x1 = xb;
    }
    lo = std::min({lo, x0, x1});
    hi = std::max({hi, x0, x1});
  }

  // Whether corner p (not a, b or c) keeps b from being an ear: a reflex or flat corner in the
  // closed triangle (a, b, c). A corner at the place of a or c (a pinched polygon) cannot block.
  bool blocks(int p, int a, int b, int c, double lx, double ly, double hx, double hy) {
    ++report_.work;
    if (p == a || p == c) return false;
    const Node& P = at(p);
    if (P.x < lx || P.x > hx || P.y < ly || P.y > hy) return false;
    if (same_point(p, a) || same_point(p, c)) return false;
    if (orient(a, b, p) < 0 || orient(b, c, p) < 0 || orient(c, a, p) < 0) return false;
    return orient(P.prev, p, P.next) <= 0;
  }

  // b is an ear: no corner of the cells the triangle (a, b, c) crosses blocks it.
  bool is_ear(int b) {
    const int a = at(b).prev, c = at(b).next;
    const double lx = std::min({at(a).x, at(b).x, at(c).x}), hx = std::max({at(a).x, at(b).x, at(c).x});
    const double ly = std::min({at(a).y, at(b).y, at(c).y}), hy = std::max({at(a).y, at(b).y, at(c).y});
    const double ey = 1e-7 * ch_, ex = 1e-7 * cw_;  // rounding of the cell borders
    for (int r = row(ly), r1 = row(hy); r <= r1; ++r) {
      const double y0 = std::max(ly, gy_ + r * ch_ - ey), y1 = std::min(hy, gy_ + (r + 1) * ch_ + ey);
      double lo = hx, hi = lx;
      clip_x(a, b, y0, y1, lo, hi);
      clip_x(b, c, y0, y1, lo, hi);
      clip_x(c, a, y0, y1, lo, hi);
      if (lo > hi) continue;
      for (int k = col(std::max(lx, lo - ex)), k1 = col(std::min(hx, hi + ex)); k <= k1; ++k) {
        ++report_.work;
        for (int p = cells_[static_cast<size_t>(r * gw_ + k)]; p >= 0; p = at(p).next_z)
          if (p != b && blocks(p, a, b, c, lx, ly, hx, hy)) return false;
      }
    }
    return true;
  }

  // Removes collinear and coincident corners (zero-area triangles); a removal makes the
  // predecessor worth another look. Returns whether anything was removed.
  bool remove_flat(int& start, int& m) {
    bool any = false;
    int p = start;
    for (long long left = m; left > 0 && m > 3;) {
      ++report_.work;
      const int a = at(p).prev, b = at(p).next;
      if (orient(a, p, b) == 0) {
        emit(a, p, b);
        unlink(p);
        --m;
        any = true;
        p = a;
      } else {
        p = b;
        --left;
      }
    }
    start = p;
    return any;
  }

  // Interior of the polygon just around a, in the direction of b (the wedge left of a's edges).
  bool locally_inside(int a, int b) {
    const int ap = at(a).prev, an = at(a).next;
    if (orient(ap, a, an) > 0) return orient(a, an, b) >= 0 && orient(a, b, ap) >= 0;
    return orient(a, b, ap) > 0 || orient(a, an, b) > 0;
  }

  static int sign(double v) { return (v > 0) - (v < 0); }

  bool on_segment(int p, int q, int r) {  // q, collinear with p and r, lies in their bounding box
    return at(q).x <= std::max(at(p).x, at(r).x) && at(q).x >= std::min(at(p).x, at(r).x) &&
           at(q).y <= std::max(at(p).y, at(r).y) && at(q).y >= std::min(at(p).y, at(r).y);
  }

  // Segments p1-q1 and p2-q2 cross; with touch, touching (an end on the other segment) counts.
  bool crosses(int p1, int q1, int p2, int q2, bool touch) {
    const int o1 = sign(orient(p1, q1, p2)), o2 = sign(orient(p1, q1, q2));
    const int o3 = sign(orient(p2, q2, p1)), o4 = sign(orient(p2, q2, q1));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    if (!touch) return false;
    return (o1 == 0 && on_segment(p1, p2, q1)) || (o2 == 0 && on_segment(p1, q2, q1)) ||
           (o3 == 0 && on_segment(p2, p1, q2)) || (o4 == 0 && on_segment(p2, q1, q2));
  }

  // Cuts off corners p, p.next where edge p.prev-p crosses edge p.next-p.next.next: the
  // self-intersecting quad (a, p, q, b) becomes the triangles (a, p, b) and (p, q, b).
  bool cure_crossings(int& start, int& m) {
    bool any = false;
    int p = start;
    for (long long left = m; left > 0 && m > 3; --left) {
      ++report_.work;
      const int a = at(p).prev, q = at(p).next, b = at(q).next;
      if (a != b && crosses(a, p, q, b, false) && locally_inside(a, b) && locally_inside(b, a)) {
        emit(a, p, b);
        emit(p, q, b);
        unlink(p);
        unlink(q);
        m -= 2;
        ++report_.cured;
        any = true;
        p = b;
        continue;
      }
      p = q;
    }
    start = p;
    return any;
  }

  // Whether the diagonal a-b lies inside the ring: locally inside at both ends, crossing no edge,
  // and its midpoint inside (even-odd rule).
  bool inside_diagonal(int a, int b, int m) {
    if (!locally_inside(a, b) || !locally_inside(b, a)) return false;
    const double lx = std::min(at(a).x, at(b).x), hx = std::max(at(a).x, at(b).x);
    const double ly = std::min(at(a).y, at(b).y), hy = std::max(at(a).y, at(b).y);
    const int ca = at(a).corner, cb = at(b).corner;
    const double mx = (at(a).x + at(b).x) / 2, my = (at(a).y + at(b).y) / 2;
    bool inside = false;
    int p = a;
    report_.work += m;
    for (int i = 0; i < m; ++i, p = at(p).next) {
      const int n = at(p).next;
      const Node &P = at(p), &N = at(n);
      if (!((P.x > hx && N.x > hx) || (P.x < lx && N.x < lx) || (P.y > hy && N.y > hy) || (P.y < ly && N.y < ly)) &&
          P.corner != ca && P.corner != cb && N.corner != ca && N.corner != cb && crosses(p, n, a, b, true))
        return false;
      if ((P.y > my) != (N.y > my) && mx < (N.x - P.x) * (my - P.y) / (N.y - P.y) + P.x) inside = !inside;
    }
    return inside;
  }

  // Splits the ring along the first diagonal that lies inside it; pushes both halves.
  bool split(int start, int m, std::vector<std::pair<int, int>>& todo) {
    int a = start;
    for (int i = 0; i < m; ++i, a = at(a).next) {
      int b = at(at(a).next).next;
      for (int s = 2; s + 1 < m; ++s, b = at(b).next) {  // b is s corners after a
        if (report_.work > limit_) return false;
        if (at(a).corner == at(b).corner || !inside_diagonal(a, b, m)) continue;
        const int a2 = static_cast<int>(nodes_.size()), b2 = a2 + 1;
        const int an = at(a).next, bp = at(b).prev;
        nodes_.push_back(Node{at(a).x, at(a).y, at(a).corner, b2, an});
        nodes_.push_back(Node{at(b).x, at(b).y, at(b).corner, bp, a2});
        at(a).next = b;
        at(b).prev = a;
        at(an).prev = a2;
        at(bp).next = b2;
        ++report_.splits;
        todo.emplace_back(a, m + 1 - s);  // a, b, and the corners after b
        todo.emplace_back(a2, s + 1);     // a2, the corners between a and b, b2
        return true;
      }
    }
    return false;
  }

  void fan(int start, int m) {
    ++report_.fans;
    int p = at(start).next;
    for (int i = 0; i + 2 < m; ++i, p = at(p).next) emit(start, p, at(p).next);
  }

  void clip_ring(int ear, int m, std::vector<std::pair<int, int>>& todo) {
    if (report_.work > limit_) return fan(ear, m);
    index_ring(ear, m);
    int stop = ear;
    while (m > 3) {
      if (++report_.work > limit_) return fan(ear, m);
      const int a = at(ear).prev, c = at(ear).next;
      if (orient(a, ear, c) > 0 && is_ear(ear)) {
        emit(a, ear, c);
        unlink(ear);
        --m;
        ear = stop = at(c).next;  // skipping c keeps the triangles local (no fan growing from a)
        continue;
      }
      ear = c;
      if (ear != stop) continue;
      // a lap without an ear
      if (remove_flat(ear, m)) {
        ++report_.flat_removals;
      } else if (!cure_crossings(ear, m)) {
        if (split(ear, m, todo)) return;
        return fan(ear, m);
      }
      stop = ear;
    }
    if (m == 3) emit(at(ear).prev, ear, at(ear).next);
  }
};

}  // namespace

EarClipReport ear_clip_polygon(const std::vector<Eigen::Vector2d>& q, std::vector<int>& tri, long long work_limit) {
  if (q.size() < 3) return {};
  tri.reserve(tri.size() + 3 * (q.size() - 2));
  return Clipper(q, tri, work_limit).run();
}

}  // namespace meshmark
