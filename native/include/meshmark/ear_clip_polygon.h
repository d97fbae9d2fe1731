// meshmark: ear clipping of one large planar polygon with a grid index of its corners (about O(n log n)).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace meshmark {

struct EarClipReport {
  long long work = 0;        // corner and cell visits (the unit of work_limit)
  int flat_removals = 0;     // stalls resolved by removing collinear/coincident corners
  int cured = 0;             // crossing edge pairs cut off (self-intersecting input)
  int splits = 0;            // stalls resolved by splitting the ring along a diagonal
  int fans = 0;              // rings (or the rest of the work, over work_limit) finished as a fan
};

// Triangulates the closed polygon q[0..n-1] (2D, counter-clockwise, n >= 3) and appends n - 2
// triangles of corner positions (0..n-1) to `tri`, each in the polygon's winding; every corner is
// used. The corners form a doubly linked ring; a corner is clipped when it is convex and no reflex or
// flat corner lies in its triangle (only those can block an ear of a simple polygon), found through
// a uniform grid of about one corner per cell: a test visits only the cells its triangle crosses.
// The scan goes round the ring, clipping as it goes (and skipping the corner after each ear). When a whole lap finds no ear (rounding,
// degenerate or self-intersecting input): collinear/coincident corners are removed as zero-area
// triangles, then adjacent crossing edges are cut off, then the ring is split along a diagonal that
// lies inside it; a ring where none of these applies is finished as a fan, as is everything left
// once `work` passes work_limit (< 0: 2e7 + 300 n log2 n, seconds at worst). For a simple polygon
// the result is a triangulation of it (no triangle outside it) unless a fan was needed; the result
// is the same on every machine. Deterministic, no allocation beyond O(n).
EarClipReport ear_clip_polygon(const std::vector<Eigen::Vector2d>& q, std::vector<int>& tri,
                               long long work_limit = -1);

}  // namespace meshmark
