// meshmark: pybind11 bindings, one bind_* function per thesis area, called from module.cpp.
#pragma once
#include <pybind11/pybind11.h>

#include "meshmark/mesh.h"

#include <utility>

namespace meshmark::python {

// The array views the bindings take from numpy (no copy when the dtype and layout match) and the
// GIL release of the long native calls; `using namespace meshmark::python::arrays;` in a bind_*.cpp.
namespace arrays {
using VRef = Eigen::Ref<const MatrixX3dR>;       // (n, 3) float64 vertices
using TRef = Eigen::Ref<const MatrixX3iR>;       // (t, 3) int32 triangles
using IRef = Eigen::Ref<const VectorXi>;         // (n,) int32
using BRef = Eigen::Ref<const VectorXb>;         // (n,) uint8 flags
using Release = pybind11::call_guard<pybind11::gil_scoped_release>;
}  // namespace arrays

// Faces passed from Python as (indices int32, offsets int64) arrays.
inline Polygons make_polygons(VectorXi indices, VectorXo offsets) {
  Polygons P;
  P.indices = std::move(indices);
  P.offsets = std::move(offsets);
  return P;
}

void bind_mesh(pybind11::module_& m);  // validation, topology, geometry, PCA, info (bind_mesh.cpp)
void bind_io(pybind11::module_& m);    // read_mesh / write_mesh (bind_io.cpp)
void bind_laplacian(pybind11::module_& m);  // ch. 7 Laplacian-coordinate watermark (bind_laplacian.cpp)
void bind_attacks(pybind11::module_& m);    // attacks: similarity, noise, smoothing, quantization, ... (bind_attacks.cpp)
void bind_metrics(pybind11::module_& m);    // distortion metrics: RMSE, surface distance, normal degradation (bind_metrics.cpp)
void bind_radial(pybind11::module_& m);     // ch. 6 Cho / Yang radial watermarks, §6.4 steganalyzer (bind_radial.cpp)
void bind_analysis(pybind11::module_& m);   // ch. 3-5 normal and curvature degradation, quantization levels (bind_analysis.cpp)
void bind_stego(pybind11::module_& m);      // §4.3.2 LSB steganography, Chao et al. 2009 baseline (bind_stego.cpp)
void bind_steganalysis(pybind11::module_& m);  // ch. 8 steganalysis features YANG208 / LFS76 / NVT36 (bind_steganalysis.cpp)
void bind_coding(pybind11::module_& m);
void bind_tracing(pybind11::module_& m);     // informed tracing: closest points, similarity ICP, low-pass patterns (bind_tracing.cpp)     // convolutional code + soft Viterbi, keyed-code search (bind_coding.cpp)

}  // namespace meshmark::python
