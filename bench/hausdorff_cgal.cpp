// meshmark's bounded one-sided Hausdorff distance against CGAL's
// Polygon_mesh_processing::bounded_error_Hausdorff_distance, timed in the same process on the same
// meshes (docs/metrics.md, "Ours or CGAL's"). Both on one core (CGAL::Sequential_tag), both at the
// same relative tolerance: ours stops at upper <= lower (1 + 1e-2) (the Python default), CGAL gets the
// absolute error bound 1e-2 x our lower bound. Attacks: our uniform noise A = 0.25 % (seed 1) and our
// CGAL edge-collapse simplification to 50 %, as in native/tests/test_hausdorff_cgal.cpp.
//
// Build (a build tree of this repository configured with -DMESHMARK_BUILD_BENCH=ON, e.g. build/wt):
//     ninja -C build/wt meshmark_bench_hausdorff && build/wt/meshmark_bench_hausdorff [mesh ...]
// Mesh paths are relative to /work/shared/meshes (MESHMARK_SHARED_MESHES).
#include "../native/tests/cgal_oracle.h"
#include "meshmark/add_noise.h"
#include "meshmark/hausdorff_distance.h"
#include "meshmark/simplify.h"

#include <CGAL/Polygon_mesh_processing/distance.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#ifndef MESHMARK_SHARED_MESHES
#define MESHMARK_SHARED_MESHES "/work/shared/meshes"
#endif

using namespace meshmark;
using namespace meshmark::cgal_oracle;
namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

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
    std::fprintf(stderr, "%s %s dir %d: meshmark %.3f s, CGAL running\n", mesh.c_str(), attack, dir, t_ours);
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
    const Tri m = load(std::string(MESHMARK_SHARED_MESHES) + "/" + rel);
    const std::string name = rel.substr(rel.find_last_of('/') + 1);
    compare(name, "noise 0.25%", m, Tri{add_noise(m.V, m.T, NoiseKind::Uniform, 0.0025, 1), m.T});
    const SimplifiedMesh s = simplify(m.V, m.T, 0.5);
    compare(name, "simplify 50%", m, Tri{s.V, s.T});
  }
  return 0;
}
