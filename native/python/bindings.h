// meshmark: pybind11 bindings, one bind_* function per thesis area, called from module.cpp.
#pragma once
#include <pybind11/pybind11.h>

#include "meshmark/mesh.h"

#include <utility>

namespace meshmark::python {

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

}  // namespace meshmark::python
