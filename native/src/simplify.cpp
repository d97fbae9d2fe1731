// Edge-collapse simplification through CGAL. This is the only meshmark translation unit that
// includes CGAL's Surface_mesh and simplification headers (they dominate a cold build).
#include "meshmark/simplify.h"
#include "meshmark/error.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>

#include <array>
#include <cmath>
#include <sstream>
#include <vector>

namespace meshmark {

namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using SM = CGAL::Surface_mesh<Point>;
namespace SMS = CGAL::Surface_mesh_simplification;
namespace PMP = CGAL::Polygon_mesh_processing;

// Stops once the mesh has at most `target` faces (CGAL 5.5 only ships edge-count predicates).
struct FaceCountStop {
  std::size_t target;
  template <typename F, typename Profile>
  bool operator()(const F&, const Profile& profile, std::size_t, std::size_t) const {
    return profile.surface_mesh().number_of_faces() <= target;
  }
};

}  // namespace

SimplifiedMesh simplify(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T, double fraction) {
  if (!(fraction > 0 && fraction <= 1)) {
    std::ostringstream s;
    s << "simplification fraction (of the faces kept) must be in (0, 1], got " << fraction;
    throw MeshError(s.str());
  }
  const auto t = static_cast<std::size_t>(T.rows());
  const auto target = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(t)));
  if (target < 4) {
    std::ostringstream s;
    s << "mesh too small to simplify: " << t << " triangles x fraction " << fraction << " = " << target
      << " triangles; the target must be at least 4";
    throw MeshError(s.str());
  }
  // Referenced vertices only, as a polygon soup; then oriented and made manifold.
  std::vector<Index> remap(static_cast<size_t>(V.rows()), -1);
  std::vector<Point> pts;
  std::vector<std::array<std::size_t, 3>> soup(t);
  for (std::size_t f = 0; f < t; ++f)
    for (int k = 0; k < 3; ++k) {
      Index& r = remap[T(f, k)];
      if (r < 0) {
        r = static_cast<Index>(pts.size());
        pts.emplace_back(V(T(f, k), 0), V(T(f, k), 1), V(T(f, k), 2));
      }
      soup[f][k] = static_cast<std::size_t>(r);
    }
  PMP::orient_polygon_soup(pts, soup);
  SM mesh;
  PMP::polygon_soup_to_polygon_mesh(pts, soup, mesh);
  if (mesh.number_of_faces() == 0) throw MeshError("simplify: the triangles do not form a surface CGAL can simplify");

  if (target < mesh.number_of_faces()) {
    SMS::GarlandHeckbert_plane_policies<SM, K> gh(mesh);
    SMS::edge_collapse(mesh, FaceCountStop{target},
                       CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
  }
  mesh.collect_garbage();

  SimplifiedMesh out;
  std::vector<Index> vid(mesh.number_of_vertices(), -1);
  Index nv = 0;
  out.T.resize(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  Eigen::Index f = 0;
  for (SM::Face_index fi : mesh.faces()) {
    int k = 0;
    for (SM::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(fi), mesh)) {
      Index& r = vid[static_cast<size_t>(v)];
      if (r < 0) r = nv++;
      if (k < 3) out.T(f, k) = r;
      ++k;
    }
    ++f;
  }
  out.V.resize(nv, 3);
  for (SM::Vertex_index v : mesh.vertices()) {
    const Index r = vid[static_cast<size_t>(v)];
    if (r < 0) continue;
    const Point& p = mesh.point(v);
    out.V.row(r) << p.x(), p.y(), p.z();
  }
  return out;
}

}  // namespace meshmark
