#include "bindings.h"

#include "meshmark/read_mesh.h"
#include "meshmark/write_mesh.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

void bind_io(py::module_& m) {
  m.def("read_mesh", [](const std::string& path, bool drop_collapsed) {
          MeshFile f;
          {
            py::gil_scoped_release release;
            f = read_mesh(path, drop_collapsed);
          }
          py::dict d;
          d["V"] = std::move(f.V);
          d["indices"] = std::move(f.P.indices);
          d["offsets"] = std::move(f.P.offsets);
          d["format"] = f.format;
          d["binary"] = f.binary;
          d["float32"] = f.float32;
          d["n_file_faces"] = f.n_file_faces;
          d["n_dropped_faces"] = f.n_dropped_faces;
          return d;
        }, py::arg("path"), py::arg("drop_collapsed") = true);

  m.def("write_mesh", [](const std::string& path, Eigen::Ref<const MatrixX3dR> V, VectorXi idx, VectorXo off,
                         bool binary, bool float32, int precision, int decimals) {
          Polygons P;
          P.indices = std::move(idx);
          P.offsets = std::move(off);
          WriteOptions o;
          o.binary = binary;
          o.float32 = float32;
          o.precision = precision;
          o.decimals = decimals;
          py::gil_scoped_release release;
          write_mesh(path, V, P, o);
        }, py::arg("path"), py::arg("V"), py::arg("indices"), py::arg("offsets"), py::arg("binary") = true,
        py::arg("float32") = false, py::arg("precision") = 17, py::arg("decimals") = -1);
}

}  // namespace meshmark::python
