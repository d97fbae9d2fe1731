#include "bindings.h"

#include "meshmark/error.h"
#include "meshmark/kirchhoff_matrix.h"
#include "meshmark/laplacian_coordinates.h"
#include "meshmark/laplacian_watermark.h"
#include "meshmark/mean_edge_length.h"
#include "meshmark/vertex_adjacency.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using VRef = Eigen::Ref<const MatrixX3dR>;
using ERef = Eigen::Ref<const MatrixX2iR>;

LaplacianHistogram make_hist(VectorXi bin, VectorXi counts, double lo, double hi) {
  LaplacianHistogram h;
  h.K = static_cast<int>(counts.size());
  h.lo = lo;
  h.hi = hi;
  h.delta = (hi - lo) / h.K;
  h.bin = std::move(bin);
  h.counts = std::move(counts);
  return h;
}
}  // namespace

void bind_laplacian(py::module_& m) {
  m.def("kirchhoff_matrix", [](Index n, ERef E, double eps) {
          // returned as (rows, cols, values) triplets for scipy.sparse.coo_matrix
          const Eigen::SparseMatrix<double> M = kirchhoff_matrix(n, E, eps);
          std::vector<Index> r, c;
          std::vector<double> v;
          for (int k = 0; k < M.outerSize(); ++k)
            for (Eigen::SparseMatrix<double>::InnerIterator it(M, k); it; ++it) {
              r.push_back(static_cast<Index>(it.row()));
              c.push_back(static_cast<Index>(it.col()));
              v.push_back(it.value());
            }
          return py::make_tuple(r, c, v);
        }, py::arg("n_vertices"), py::arg("E"), py::arg("eps") = 1e-5);

  m.def("laplacian_coordinates", [](VRef V, ERef E, double eps) {
          py::gil_scoped_release release;
          return laplacian_coordinates(V, vertex_adjacency(static_cast<Index>(V.rows()), E), eps);
        }, py::arg("V"), py::arg("E"), py::arg("eps") = 0.0);

  m.def("mean_edge_length", [](VRef V, ERef E) { return mean_edge_length(V, E); }, py::arg("V"), py::arg("E"),
        py::call_guard<py::gil_scoped_release>());

  m.def("laplacian_lengths", [](VRef V, ERef E, double eps) {
          py::gil_scoped_release release;
          return laplacian_lengths(V, vertex_adjacency(static_cast<Index>(V.rows()), E), eps);
        }, py::arg("V"), py::arg("E"), py::arg("eps") = 0.0);

  m.def("laplacian_histogram", [](Eigen::Ref<const Eigen::VectorXd> d, int K, double lo, double hi,
                                  Eigen::Ref<const VectorXb> mask) {
          if (mask.size() != d.size()) throw MeshError("mask and d differ in length");
          LaplacianHistogram h = laplacian_histogram(d, K, lo, hi, mask);
          return py::make_tuple(std::move(h.bin), std::move(h.counts));
        }, py::arg("d"), py::arg("K"), py::arg("lo"), py::arg("hi"), py::arg("mask"));

  m.def("laplacian_embed", [](VRef V, ERef E, VectorXi bin, VectorXi counts, double lo, double hi,
                              std::vector<int> pairs, std::vector<int> bits, int n_robust, double eps,
                              bool thesis_exact, double scale) {
          if (bin.size() != V.rows()) throw MeshError("bin and V differ in length");
          const LaplacianHistogram h = make_hist(std::move(bin), std::move(counts), lo, hi);
          LaplacianEmbedOptions o;
          o.n_robust = n_robust;
          o.eps = eps;
          o.thesis_exact = thesis_exact;
          o.scale = scale;
          LaplacianEmbedResult r;
          {
            py::gil_scoped_release release;
            r = laplacian_embed(V, vertex_adjacency(static_cast<Index>(V.rows()), E), h, pairs, bits, o);
          }
          return py::make_tuple(std::move(r.V), std::move(r.d_target), r.n_moved);
        }, py::arg("V"), py::arg("E"), py::arg("bin"), py::arg("counts"), py::arg("lo"), py::arg("hi"),
        py::arg("pairs"), py::arg("bits"), py::arg("n_robust") = 5, py::arg("eps") = 1e-5,
        py::arg("thesis_exact") = false, py::arg("scale") = 1.0);
}

}  // namespace meshmark::python
