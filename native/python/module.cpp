// meshmark._core: the compiled module behind the meshmark Python package.
#include "bindings.h"
#include "meshmark/error.h"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "meshmark native core (C++17). Use the meshmark package rather than this module directly.";
  // meshmark::MeshError -> meshmark.MeshError, a subclass of ValueError.
  py::register_exception<meshmark::MeshError>(m, "MeshError", PyExc_ValueError);
  meshmark::python::bind_mesh(m);
  meshmark::python::bind_io(m);
  meshmark::python::bind_laplacian(m);
  meshmark::python::bind_attacks(m);
  meshmark::python::bind_metrics(m);
  meshmark::python::bind_radial(m);
  meshmark::python::bind_analysis(m);
  meshmark::python::bind_stego(m);
  meshmark::python::bind_steganalysis(m);
  meshmark::python::bind_coding(m);
  meshmark::python::bind_tracing(m);
}
