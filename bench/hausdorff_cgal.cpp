// meshmark's bounded one-sided Hausdorff distance against CGAL's
// Polygon_mesh_processing::bounded_error_Hausdorff_distance, timed in the same process on the same
// meshes (docs/metrics.md, "Ours or CGAL's"). Both on one core (CGAL::Sequential_tag), both at the
// same relative tolerance: ours stops at upper <= lower (1 + 1e-2) (the Python default), CGAL gets the
// absolute error bound 1e-2 x our lower bound. Attacks: our uniform noise A = 0.25 % (seed 1) and our
// CGAL edge-collapse simplification to 50 %, as in native/tests/test_hausdorff_cgal.cpp.
//
// Build (a configured build tree of this repository, e.g. build/wt, with MESHMARK_BUILD_TESTS=ON):
//     ninja -C build/wt meshmark_bench_hausdorff && build/wt/meshmark_bench_hausdorff [mesh ...]
// Mesh paths are relative to /work/shared/meshes (MESHMARK_SHARED_MESHES).
#include "meshmark/add_noise.h"
#include "meshmark/hausdorff_distance.h"
#include "meshmark/read_mesh.h"
#include "meshmark/simplify.h"
#include "meshmark/triangulate.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#ifndef MESHMARK_SHARED_MESHES
#define MESHMARK_SHARED_MESHES "/work/shared/meshes"
#endif

using namespace meshmark;
namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;

namespace {

struct Tri {
  MatrixX3dR V;
  MatrixX3iR T;
};

// Referenced vertices only, triangulated (the same loading as the CGAL oracle test).
Tri load(const std::string& rel) {
  const MeshFile f = read_mesh(std::string(MESHMARK_SHARED_MESHES) + "/" + rel);
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

SM to_cgal(const Tri& m) {
  std::vector<K::Point_3> pts;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) pts.emplace_back(m.V(i, 0), m.V(i, 1), m.V(i, 2));
  std::vector<std::array<std::size_t, 3>> faces;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    faces.push_back({static_cast<std::size_t>(m.T(t, 0)), static_cast<std::size_t>(m.T(t, 1)),
                     static_cast<std::size_t>(m.T(t, 2))});
  SM sm;
  PMP::polygon_soup_to_polygon_mesh(pts, faces, sm);
  return sm;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void compare(const std::string& mesh, const char* attack, const Tri& a, const Tri& b) {
  const SM sa = to_cgal(a), sb = to_cgal(b);  // conversion not timed (ours takes the arrays as they are)
  for (int dir = 0; dir < 2; ++dir) {
    const Tri& x = dir ? b : a;
    const Tri& y = dir ? a : b;
    auto t0 = std::chrono::steady_clock::now();
    const HausdorffBound ours = hausdorff_distance(x.V, x.T, y.V, y.T, 1e-2, 0.0, 3000000);
    const double t_ours = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const double cgal =
        PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(dir ? sb : sa, dir ? sa : sb, 1e-2 * ours.lower);
    const double t_cgal = seconds_since(t0);
    std::printf("| %s | %s | %s | %lld | [%.4e, %.4e]%s | %.4e | %.4f | %.3f | %.3f | %.2f |\n", mesh.c_str(), attack,
                dir ? "attacked -> original" : "original -> attacked", static_cast<long long>(x.T.rows()), ours.lower,
                ours.upper, ours.converged ? "" : " cap", cgal, ours.lower / cgal, t_ours, t_cgal, t_cgal / t_ours);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) meshes.emplace_back(argv[i]);
  if (meshes.empty()) meshes = {"classic/bunny.obj", "classic/horse.ply", "classic/elephant.off", "classic/fandisk.obj"};
  std::printf("| mesh | attack | direction | triangles of A | meshmark [lower, upper] | CGAL | lower / CGAL | "
              "meshmark s | CGAL s | CGAL / meshmark time |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& rel : meshes) {
    const Tri m = load(rel);
    const std::string name = rel.substr(rel.find_last_of('/') + 1);
    compare(name, "noise 0.25%", m, Tri{add_noise(m.V, m.T, NoiseKind::Uniform, 0.0025, 1), m.T});
    const SimplifiedMesh s = simplify(m.V, m.T, 0.5);
    compare(name, "simplify 50%", m, Tri{s.V, s.T});
  }
  return 0;
}
