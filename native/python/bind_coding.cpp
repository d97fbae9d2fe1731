#include "bindings.h"

#include "meshmark/convolutional_code.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

void bind_coding(py::module_& m) {
  m.def(
      "conv_encode",
      [](py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> u, std::vector<int> generators, int K,
         bool tail_biting) {
        std::vector<std::uint8_t> in(u.data(), u.data() + u.size());
        std::vector<std::uint8_t> c;
        {
          py::gil_scoped_release nogil;
          c = conv_encode(in, generators, K, tail_biting);
        }
        return py::array_t<std::uint8_t>(static_cast<py::ssize_t>(c.size()), c.data());
      },
      py::arg("u"), py::arg("generators"), py::arg("K"), py::arg("tail_biting"),
      "Convolutional encoding (docs/coding.md): code bits interleaved per step (uint8 0/1).");
  m.def(
      "viterbi_decode",
      [](py::array_t<double, py::array::c_style | py::array::forcecast> llr, std::vector<int> generators, int K,
         int n_info, bool tail_biting, int wrap) {
        std::vector<double> y(llr.data(), llr.data() + llr.size());
        std::vector<std::uint8_t> u;
        {
          py::gil_scoped_release nogil;
          u = viterbi_decode(y, generators, K, n_info, tail_biting, wrap);
        }
        return py::array_t<std::uint8_t>(static_cast<py::ssize_t>(u.size()), u.data());
      },
      py::arg("llr"), py::arg("generators"), py::arg("K"), py::arg("n_info"), py::arg("tail_biting"),
      py::arg("wrap") = 48,
      "Soft-input Viterbi decoding (llr > 0 means 1); tail-biting by wrap-around over `wrap` steps.");
}

}  // namespace meshmark::python
