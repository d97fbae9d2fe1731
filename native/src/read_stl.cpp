// Reading STL, binary and ASCII, through CGAL's reader (which welds corners on exactly equal
// coordinates, in order of first appearance). The binary triangle count is checked against the file
// size before CGAL sees the file.
#include "read_common.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/IO/STL.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

namespace meshmark::detail {

namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;
using Polygon = std::vector<std::size_t>;

template <class PointT>
void fill_mesh(MeshFile& out, const std::vector<PointT>& pts, const std::vector<Polygon>& polys) {
  out.V.resize(static_cast<Eigen::Index>(pts.size()), 3);
  for (size_t i = 0; i < pts.size(); ++i) {
    out.V(i, 0) = pts[i].x();
    out.V(i, 1) = pts[i].y();
    out.V(i, 2) = pts[i].z();
  }
  size_t corners = 0;
  for (const auto& p : polys) corners += p.size();
  out.P.indices.resize(static_cast<Eigen::Index>(corners));
  out.P.offsets.resize(static_cast<Eigen::Index>(polys.size()) + 1);
  out.P.offsets[0] = 0;
  Offset c = 0;
  for (size_t f = 0; f < polys.size(); ++f) {
    for (std::size_t v : polys[f]) {
      // Indices beyond int32 (or wrapped negatives from the readers) are reported by validation.
      out.P.indices[c++] = v > static_cast<std::size_t>(INT32_MAX) ? -1 : static_cast<Index>(v);
    }
    out.P.offsets[static_cast<Eigen::Index>(f) + 1] = c;
  }
}

}  // namespace

void read_stl(const Reader& r, const std::string& path, long long size, MeshFile& out) {
  std::vector<Point> pts;
  std::vector<Polygon> polys;
  std::ifstream is(path, std::ios::binary);
  if (!is) r.fail("cannot open the file");
  char head[84] = {0};
  is.read(head, 84);
  const bool looks_ascii = std::strncmp(head, "solid", 5) == 0;
  std::uint32_t n_tri = 0;
  std::memcpy(&n_tri, head + 80, 4);
  const bool exact_binary = size >= 84 && size == 84 + 50LL * n_tri;
  out.binary = !looks_ascii || exact_binary;
  out.float32 = out.binary;  // ASCII STL stores decimal text, read as double
  if (out.binary) {
    if (size < 84) r.fail("truncated binary STL: " + std::to_string(size) + " bytes, less than the 84-byte header");
    if (size < 84 + 50LL * n_tri)
      r.fail("truncated binary STL: the header declares " + std::to_string(n_tri) + " triangles (" +
             std::to_string(84 + 50LL * n_tri) + " bytes) but the file has " + std::to_string(size) + " bytes");
    if (n_tri == 0) r.fail("binary STL with no triangles");
  }
  is.clear();
  is.seekg(0);
  std::vector<std::array<std::size_t, 3>> tris;
  const bool ok = CGAL::IO::read_STL(is, pts, tris, CGAL::parameters::verbose(false).use_binary_mode(out.binary));
  if (!ok || tris.empty()) r.fail(out.binary ? "malformed binary STL" : "malformed ASCII STL (truncated, or a facet without 3 vertices)");
  polys.reserve(tris.size());
  for (const auto& t : tris) polys.push_back({t[0], t[1], t[2]});
  fill_mesh(out, pts, polys);
}

}  // namespace meshmark::detail
