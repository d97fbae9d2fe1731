// Bindings of the attacks (meshmark.attacks): numpy in, numpy out; the Python layer validates.
#include "bindings.h"

#include "meshmark/add_noise.h"
#include "meshmark/boundary.h"
#include "meshmark/cotangent_smooth.h"
#include "meshmark/crop_plane.h"
#include "meshmark/dithered_quantize.h"
#include "meshmark/error.h"
#include "meshmark/laplacian_smooth.h"
#include "meshmark/mean_centroid_distance.h"
#include "meshmark/permute_mesh.h"
#include "meshmark/quantize.h"
#include "meshmark/remesh.h"
#include "meshmark/similarity_transform.h"
#include "meshmark/simplify.h"
#include "meshmark/subdivide.h"
#include "meshmark/unique_edges.h"
#include "meshmark/vertex_adjacency.h"
#include "meshmark/vertex_normals.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using VRef = Eigen::Ref<const MatrixX3dR>;
using TRef = Eigen::Ref<const MatrixX3iR>;
using WordMat = Eigen::Matrix<std::uint64_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Release = py::call_guard<py::gil_scoped_release>;


NoiseKind noise_kind(const std::string& s) {
  if (s == "uniform") return NoiseKind::Uniform;
  if (s == "gaussian") return NoiseKind::Gaussian;
  if (s == "normal") return NoiseKind::Normal;
  if (s == "tangent") return NoiseKind::Tangent;
  throw MeshError("unknown noise kind '" + s + "' (expected uniform, gaussian, normal or tangent)");
}

DitherWord dither_word(const std::string& s) {
  if (s == "fixed32") return DitherWord::Fixed32;
  if (s == "float64") return DitherWord::Float64;
  throw MeshError("unknown dither word '" + s + "' (expected fixed32 or float64)");
}
}  // namespace

void bind_attacks(py::module_& m) {
  m.def("similarity_transform", &similarity_transform, py::arg("V"), py::arg("R"), py::arg("s"), py::arg("t"), Release());
  m.def("axis_angle_rotation", &axis_angle_rotation, py::arg("axis"), py::arg("angle_deg"));
  m.def("random_similarity_params", [](std::uint64_t seed, double log_lo, double log_hi) {
          // draw order: rotation (3 uniforms), log-uniform scale, translation (3 x uniform(-1, 1))
          Rng rng(seed);
          const Eigen::Matrix3d R = random_rotation(rng);
          const double s = std::exp(rng.uniform(log_lo, log_hi));
          const Eigen::Vector3d t(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
          return py::make_tuple(R, s, t);
        }, py::arg("seed"), py::arg("log_lo"), py::arg("log_hi"));

  m.def("permute_mesh", [](VRef V, VectorXi idx, VectorXo off, std::uint64_t seed, bool pv, bool pf) {
          PermutedMesh r;
          {
            py::gil_scoped_release release;
            r = permute_mesh(V, make_polygons(std::move(idx), std::move(off)), seed, pv, pf);
          }
          return py::make_tuple(std::move(r.V), std::move(r.P.indices), std::move(r.P.offsets),
                                std::move(r.vertex_perm), std::move(r.face_perm));
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"), py::arg("seed"), py::arg("vertices") = true,
        py::arg("faces") = true);

  m.def("mean_centroid_distance", &mean_centroid_distance, py::arg("V"), Release());
  m.def("vertex_normals", &vertex_normals, py::arg("V"), py::arg("T"), Release());
  m.def("add_noise", [](VRef V, TRef T, const std::string& kind, double A, std::uint64_t seed) {
          const NoiseKind k = noise_kind(kind);
          py::gil_scoped_release release;
          return add_noise(V, T, k, A, seed);
        }, py::arg("V"), py::arg("T"), py::arg("kind"), py::arg("strength"), py::arg("seed"));

  m.def("laplacian_smooth", [](VRef V, VectorXi idx, VectorXo off, double lambda, int iterations, bool fix_boundary) {
          py::gil_scoped_release release;
          const Index n = static_cast<Index>(V.rows());
          const EdgeList E = unique_edges(n, make_polygons(std::move(idx), std::move(off)));
          const VectorXi fixed = fix_boundary ? boundary_vertices(n, E) : VectorXi();
          return laplacian_smooth(V, vertex_adjacency(n, E.E), lambda, iterations, fixed);
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"), py::arg("lam"), py::arg("iterations"),
        py::arg("fix_boundary") = false);

  m.def("cotangent_smooth", [](VRef V, TRef T, double lambda, int iterations, bool fix_boundary) {
          py::gil_scoped_release release;
          VectorXi fixed;
          if (fix_boundary) {
            const Index n = static_cast<Index>(V.rows());
            fixed = boundary_vertices(n, unique_edges(n, Polygons::from_triangles(MatrixX3iR(T))));
          }
          return cotangent_smooth(V, T, lambda, iterations, fixed);
        }, py::arg("V"), py::arg("T"), py::arg("lam"), py::arg("iterations"), py::arg("fix_boundary") = false);

  m.def("quantize", &quantize, py::arg("V"), py::arg("bits"), Release());
  m.def("dither_bits", [](VRef V, Eigen::Ref<const VectorXi> t, Eigen::Ref<const WordMat> words, const std::string& w) {
          const DitherWord dw = dither_word(w);
          py::gil_scoped_release release;
          return dither_bits(V, t, words, dw);
        }, py::arg("V"), py::arg("t"), py::arg("words"), py::arg("word"));
  m.def("dithered_quantize", [](VRef V, Eigen::Ref<const VectorXi> t, std::uint64_t seed, const std::string& w) {
          const DitherWord dw = dither_word(w);
          py::gil_scoped_release release;
          return dithered_quantize(V, t, seed, dw);
        }, py::arg("V"), py::arg("t"), py::arg("seed"), py::arg("word"));

  m.def("simplify", [](VRef V, TRef T, double fraction) {
          SimplifiedMesh r;
          {
            py::gil_scoped_release release;
            r = simplify(V, T, fraction);
          }
          return py::make_tuple(std::move(r.V), std::move(r.T));
        }, py::arg("V"), py::arg("T"), py::arg("fraction"));

  m.def("remesh", [](VRef V, TRef T, double relative_length, int iterations) {
          RemeshedMesh r;
          {
            py::gil_scoped_release release;
            r = remesh(V, T, relative_length, iterations);
          }
          return py::make_tuple(std::move(r.V), std::move(r.T), r.target_edge_length);
        }, py::arg("V"), py::arg("T"), py::arg("relative_length"), py::arg("iterations"));

  m.def("midpoint_subdivide", [](VRef V, TRef T) {
          SubdividedMesh r;
          {
            py::gil_scoped_release release;
            r = midpoint_subdivide(V, T);
          }
          return py::make_tuple(std::move(r.V), std::move(r.T));
        }, py::arg("V"), py::arg("T"));
  m.def("loop_subdivide", [](VRef V, TRef T) {
          SubdividedMesh r;
          {
            py::gil_scoped_release release;
            r = loop_subdivide(V, T);
          }
          return py::make_tuple(std::move(r.V), std::move(r.T));
        }, py::arg("V"), py::arg("T"));

  m.def("crop_plane", [](VRef V, VectorXi idx, VectorXo off, const Eigen::Vector3d& normal, double fraction) {
          CroppedMesh r;
          {
            py::gil_scoped_release release;
            r = crop_plane(V, make_polygons(std::move(idx), std::move(off)), normal, fraction);
          }
          return py::make_tuple(std::move(r.V), std::move(r.P.indices), std::move(r.P.offsets), std::move(r.kept));
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"), py::arg("normal"), py::arg("fraction"));
}

}  // namespace meshmark::python
