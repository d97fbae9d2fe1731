// Shared meshes as CGAL Surface_meshes for the checks against CGAL (tests/test_hausdorff_cgal.cpp and
// bench/hausdorff_cgal.cpp): load a shared mesh triangulated with referenced vertices only, convert it.
#pragma once
#include "meshmark/read_mesh.h"
#include "meshmark/triangulate.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <string>
#include <vector>

namespace meshmark::cgal_oracle {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;

struct Tri {
  MatrixX3dR V;
  MatrixX3iR T;
};

// Referenced vertices only (the bunny file has 1,113 unreferenced ones), polygons triangulated.
inline Tri load(const std::string& path) {
  const MeshFile f = read_mesh(path);
  const Triangulation tr = triangulate(f.V, f.P);
  std::vector<Index> remap(static_cast<size_t>(f.V.rows()), -1);
  Tri out;
  Index n = 0;
  out.T.resize(tr.T.rows(), 3);
  for (Eigen::Index t = 0; t < tr.T.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      Index& r = remap[tr.T(t, k)];
      if (r < 0) r = n++;
      out.T(t, k) = r;
    }
  out.V.resize(n, 3);
  for (size_t i = 0; i < remap.size(); ++i)
    if (remap[i] >= 0) out.V.row(remap[i]) = f.V.row(static_cast<Eigen::Index>(i));
  return out;
}

inline SM to_cgal(const Tri& m) {
  std::vector<K::Point_3> pts;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) pts.emplace_back(m.V(i, 0), m.V(i, 1), m.V(i, 2));
  std::vector<std::array<std::size_t, 3>> faces;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    faces.push_back({static_cast<std::size_t>(m.T(t, 0)), static_cast<std::size_t>(m.T(t, 1)),
                     static_cast<std::size_t>(m.T(t, 2))});
  SM sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, faces, sm);
  return sm;
}

}  // namespace meshmark::cgal_oracle
