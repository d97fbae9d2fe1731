// Isotropic remeshing through CGAL. This is the only meshmark translation unit that includes
// CGAL's remeshing headers (they are heavy to compile).
#include "meshmark/remesh.h"
#include "meshmark/error.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <array>
#include <cmath>
#include <sstream>
#include <vector>

namespace meshmark {

namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using SM = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr double kMaxTriangles = 2e7;

}  // namespace

RemeshedMesh remesh(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                    double relative_length, int iterations) {
  if (!(relative_length > 0 && relative_length <= 100)) {
    std::ostringstream s;
    s << "remesh edge length (a multiple of the mean edge length) must be in (0, 100], got " << relative_length;
    throw MeshError(s.str());
  }
  if (iterations < 1 || iterations > 100) {
    std::ostringstream s;
    s << "remesh iterations must be in 1..100, got " << iterations;
    throw MeshError(s.str());
  }
  const auto t = static_cast<std::size_t>(T.rows());
  if (t == 0) throw MeshError("remesh: the mesh has no triangles");
  // Referenced vertices only, as a polygon soup; degenerate triangles refused.
  std::vector<Index> remap(static_cast<size_t>(V.rows()), -1);
  std::vector<Point> pts;
  std::vector<std::array<std::size_t, 3>> soup(t);
  std::size_t degenerate = 0, first_degenerate = 0;
  double area = 0;
  for (std::size_t f = 0; f < t; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Index i = T(f, k);
      if (i < 0 || i >= V.rows()) throw MeshError("remesh: a triangle refers to a vertex that does not exist");
      Index& r = remap[i];
      if (r < 0) {
        r = static_cast<Index>(pts.size());
        pts.emplace_back(V(i, 0), V(i, 1), V(i, 2));
      }
      soup[f][k] = static_cast<std::size_t>(r);
    }
    const Point &a = pts[soup[f][0]], &b = pts[soup[f][1]], &c = pts[soup[f][2]];
    const double A = std::sqrt(CGAL::cross_product(b - a, c - a).squared_length()) / 2;
    if (!(A > 0) || !std::isfinite(A)) {
      if (degenerate++ == 0) first_degenerate = f;
    }
    area += A;
  }
  if (degenerate) {
    std::ostringstream s;
    s << "remesh: " << degenerate << " of " << t << " triangles are degenerate (zero area; the first is triangle "
      << first_degenerate << "); remove them first";
    throw MeshError(s.str());
  }
  // orient_polygon_soup returns false when it had to duplicate vertices: the input is not a manifold.
  if (!PMP::orient_polygon_soup(pts, soup) || !PMP::is_polygon_soup_a_polygon_mesh(soup)) {
    throw MeshError("remesh needs an edge- and vertex-manifold surface: an edge is shared by more than two triangles "
                    "or a vertex joins separate fans ('meshmark info' counts them)");
  }
  SM mesh;
  PMP::polygon_soup_to_polygon_mesh(pts, soup, mesh);
  if (mesh.number_of_faces() != t) throw MeshError("remesh: the triangles do not form a surface CGAL can remesh");

  double total = 0;
  std::size_t ne = 0;
  for (SM::Edge_index e : mesh.edges()) {
    total += std::sqrt(CGAL::squared_distance(mesh.point(mesh.source(mesh.halfedge(e))),
                                              mesh.point(mesh.target(mesh.halfedge(e)))));
    ++ne;
  }
  const double L = relative_length * total / static_cast<double>(ne);
  const double expected = area / (std::sqrt(3.0) / 4 * L * L);  // equilateral triangles of side L
  if (!(L > 0) || !std::isfinite(L) || expected > kMaxTriangles) {
    std::ostringstream s;
    s << "remesh: target edge length " << L << " would make about " << expected
      << " triangles (at most 2e7); choose a longer edge length";
    throw MeshError(s.str());
  }
  PMP::isotropic_remeshing(faces(mesh), L, mesh, CGAL::parameters::number_of_iterations(static_cast<unsigned>(iterations)));
  mesh.collect_garbage();

  RemeshedMesh out;
  out.target_edge_length = L;
  out.V.resize(static_cast<Eigen::Index>(mesh.number_of_vertices()), 3);
  for (SM::Vertex_index v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.V.row(static_cast<Eigen::Index>(v)) << p.x(), p.y(), p.z();
  }
  out.T.resize(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  Eigen::Index f = 0;
  for (SM::Face_index fi : mesh.faces()) {
    int k = 0;
    for (SM::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(fi), mesh)) {
      if (k < 3) out.T(f, k) = static_cast<Index>(v);
      ++k;
    }
    if (k != 3) throw MeshError("remesh: CGAL returned a face that is not a triangle");
    ++f;
  }
  return out;
}

}  // namespace meshmark
