#include "bindings.h"

#include "meshmark/error.h"
#include "meshmark/kirchhoff_matrix.h"
#include "meshmark/laplacian_carrier.h"
#include "meshmark/laplacian_coordinates.h"
#include "meshmark/laplacian_range_factor.h"
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

void check_edges(const VRef& V, const ERef& E) {
  if (E.rows() && (E.minCoeff() < 0 || E.maxCoeff() >= V.rows()))
    throw MeshError("edge list refers to a vertex outside 0.." + std::to_string(V.rows() - 1));
}

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
          check_edges(V, E);
          return laplacian_lengths(V, E, eps);
        }, py::arg("V"), py::arg("E"), py::arg("eps") = 0.0);

  m.def("laplacian_lengths_scaled", [](VRef V, ERef E, double eps) {
          check_edges(V, E);
          double mel = 0;
          Eigen::VectorXd d;
          {
            py::gil_scoped_release release;
            d = laplacian_lengths(V, E, eps, &mel);
          }
          return py::make_tuple(std::move(d), mel);
        }, py::arg("V"), py::arg("E"), py::arg("eps") = 0.0,
        "(d, mean_edge_length): the Laplacian lengths (eq. 7.1.5) and the mean edge length in one pass");

  m.def("laplacian_carrier", [](VRef V, ERef E, Eigen::Ref<const MatrixX3iR> T, int kind, double scale,
                                double compress) {
          check_edges(V, E);
          if (T.rows() && (T.minCoeff() < 0 || T.maxCoeff() >= V.rows()))
            throw MeshError("triangle list refers to a vertex outside 0.." + std::to_string(V.rows() - 1));
          py::gil_scoped_release release;
          return laplacian_carrier(V, E, T, static_cast<LaplacianCarrier>(kind), scale, false, compress).value;
        }, py::arg("V"), py::arg("E"), py::arg("T"), py::arg("kind"), py::arg("scale") = 1.0, py::arg("compress") = 0.0,
        "(n,) carrier scalar s_i of laplacian_carrier.h (kind 0 thesis ||L||/scale, 1 local, 2 normal, "
        "3 cotangent local, 4 cotangent normal, 5 normal over the global unit `scale`)");

  m.def("laplacian_pair_counts", [](Eigen::Ref<const Eigen::VectorXd> d_sorted, double lo, double hi, int K,
                                    std::vector<long long> ids) {
          std::vector<long long> c1, c2;
          {
            py::gil_scoped_release release;
            laplacian_pair_counts(d_sorted, lo, hi, K, ids, c1, c2);
          }
          return py::make_tuple(c1, c2);
        }, py::arg("d_sorted"), py::arg("lo"), py::arg("hi"), py::arg("K"), py::arg("ids"));

  m.def("laplacian_range_factor", [](Eigen::Ref<const Eigen::VectorXd> d_sorted, double lo, double hi, int K,
                                     std::vector<long long> ids, double span, double min_gain) {
          py::gil_scoped_release release;
          return laplacian_range_factor(d_sorted, lo, hi, K, ids, span, min_gain);
        }, py::arg("d_sorted"), py::arg("lo"), py::arg("hi"), py::arg("K"), py::arg("ids"), py::arg("span") = 0.1,
        py::arg("min_gain") = 0.05);

  m.def("laplacian_histogram", [](Eigen::Ref<const Eigen::VectorXd> d, int K, double lo, double hi,
                                  Eigen::Ref<const VectorXb> mask) {
          if (mask.size() != d.size()) throw MeshError("mask and d differ in length");
          LaplacianHistogram h = laplacian_histogram(d, K, lo, hi, mask);
          return py::make_tuple(std::move(h.bin), std::move(h.counts));
        }, py::arg("d"), py::arg("K"), py::arg("lo"), py::arg("hi"), py::arg("mask"));

  m.def("laplacian_embed", [](VRef V, ERef E, VectorXi bin, VectorXi counts, double lo, double hi,
                              std::vector<int> pairs, std::vector<int> bits, int n_robust, double eps,
                              bool thesis_exact, double scale, int iterations, int max_rounds, int carrier,
                              Eigen::Ref<const MatrixX3iR> T, double compress) {
          if (bin.size() != V.rows()) throw MeshError("bin and V differ in length");
          check_edges(V, E);
          if (T.rows() && (T.minCoeff() < 0 || T.maxCoeff() >= V.rows()))
            throw MeshError("triangle list refers to a vertex outside 0.." + std::to_string(V.rows() - 1));
          const LaplacianHistogram h = make_hist(std::move(bin), std::move(counts), lo, hi);
          LaplacianEmbedOptions o;
          o.n_robust = n_robust;
          o.eps = eps;
          o.thesis_exact = thesis_exact;
          o.scale = scale;
          o.iterations = iterations;
          o.max_rounds = max_rounds;
          o.carrier = static_cast<LaplacianCarrier>(carrier);
          o.compress = compress;
          if (o.carrier != LaplacianCarrier::Thesis || compress > 0) o.triangles = &T;
          LaplacianEmbedResult r;
          {
            py::gil_scoped_release release;
            r = laplacian_embed(V, vertex_adjacency(static_cast<Index>(V.rows()), E), h, pairs, bits, o);
          }
          return py::make_tuple(std::move(r.V), std::move(r.d_target), r.n_moved, r.rounds, r.iterations);
        }, py::arg("V"), py::arg("E"), py::arg("bin"), py::arg("counts"), py::arg("lo"), py::arg("hi"),
        py::arg("pairs"), py::arg("bits"), py::arg("n_robust") = 5, py::arg("eps") = 1e-5,
        py::arg("thesis_exact") = false, py::arg("scale") = 1.0, py::arg("iterations") = 5,
        py::arg("max_rounds") = 8, py::arg("carrier") = 0,
        py::arg("T") = MatrixX3iR(0, 3), py::arg("compress") = 0.0);
}

}  // namespace meshmark::python
