#include "bindings.h"

#include "meshmark/codebook_disagreement.h"
#include "meshmark/convolutional_code.h"

#include <stdexcept>

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
  m.def(
      "codebook_disagreement",
      [](py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> book,
         py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> received,
         py::array_t<std::int32_t, py::array::c_style | py::array::forcecast> weights) {
        if (book.ndim() != 2 || received.ndim() != 1 || received.shape(0) != book.shape(1) || weights.ndim() != 1 ||
            weights.shape(0) != 8 * book.shape(1))
          throw std::invalid_argument("codebook_disagreement: book (W, nb), received (nb,), weights (8 nb,)");
        std::vector<std::int32_t> wt(weights.data(), weights.data() + weights.size());
        std::vector<std::int32_t> D;
        {
          py::gil_scoped_release nogil;
          D = codebook_disagreement(book.data(), book.shape(0), static_cast<int>(book.shape(1)), received.data(), wt);
        }
        return py::array_t<std::int32_t>(static_cast<py::ssize_t>(D.size()), D.data());
      },
      py::arg("book"), py::arg("received"), py::arg("weights"),
      "Weighted disagreement of every packed codeword (rows of book, MSB first) with the packed received word.");
}

}  // namespace meshmark::python
