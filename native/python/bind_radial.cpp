#include "bindings.h"

#include "meshmark/cho_margin_test.h"
#include "meshmark/cho_steganalysis.h"
#include "meshmark/cho_watermark.h"
#include "meshmark/error.h"
#include "meshmark/gaussian_mixture.h"
#include "meshmark/radial_distances.h"
#include "meshmark/radial_watermark.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using VRef = Eigen::Ref<const MatrixX3dR>;
using MRef = Eigen::Ref<const VectorXb>;

ChoMethod cho_method(const std::string& s) {
  if (s == "mean") return ChoMethod::Mean;
  if (s == "variance") return ChoMethod::Variance;
  throw MeshError("Cho method must be 'mean' or 'variance', got '" + s + "'");
}

RadialOriginMode origin_mode(const std::string& s) {
  if (s == "axis") return RadialOriginMode::Axis;
  if (s == "vertices") return RadialOriginMode::Vertices;
  throw MeshError("origin_mode must be 'axis' or 'vertices', got '" + s + "'");
}

void check_mask(const VRef& V, const MRef& mask) {
  if (mask.size() != V.rows()) throw MeshError("mask and V differ in length");
}
}  // namespace

void bind_radial(py::module_& m) {
  m.def("masked_centroid", [](VRef V, MRef mask) { return Eigen::Vector3d(masked_centroid(V, mask)); },
        py::arg("V"), py::arg("mask"));
  m.def("radial_distances", [](VRef V, MRef mask, Eigen::Vector3d c) { return radial_distances(V, mask, c); },
        py::arg("V"), py::arg("mask"), py::arg("center"));

  // --- Cho et al. ------------------------------------------------------------------------------
  m.def("cho_bins", [](Eigen::Ref<const Eigen::VectorXd> rho, int K, MRef mask) {
          ChoBins b = cho_bins(rho, K, mask);
          return py::make_tuple(std::move(b.bin), std::move(b.x), std::move(b.counts), b.rho_min, b.rho_max, b.width);
        }, py::arg("rho"), py::arg("K"), py::arg("mask"));

  m.def("cho_statistics", [](VRef V, MRef mask, int K, const std::string& method) {
          check_mask(V, mask);
          const ChoMethod mt = cho_method(method);
          ChoStatistics s;
          {
            py::gil_scoped_release release;
            s = cho_statistics(V, mask, K, mt);
          }
          return py::make_tuple(std::move(s.stat), std::move(s.counts), Eigen::Vector3d(s.center));
        }, py::arg("V"), py::arg("mask"), py::arg("K"), py::arg("method") = "mean");

  m.def("cho_embed", [](VRef V, MRef mask, int K, std::vector<int> bins, std::vector<int> bits,
                        const std::string& method, double alpha, double delta_k, double k_max, double guard,
                        int center_iters) {
          check_mask(V, mask);
          ChoEmbedOptions o;
          o.method = cho_method(method);
          o.alpha = alpha;
          o.delta_k = delta_k;
          o.k_max = k_max;
          o.guard = guard;
          o.center_iters = center_iters;
          ChoEmbedResult r;
          {
            py::gil_scoped_release release;
            r = cho_embed(V, mask, K, bins, bits, o);
          }
          py::dict d;
          d["V"] = std::move(r.V);
          d["k"] = std::move(r.k);
          d["failed_bins"] = r.failed;
          d["center"] = r.center;
          d["center_drift"] = r.drift;
          d["center_iters"] = r.iterations;
          d["n_moved"] = r.n_moved;
          d["search_evaluations"] = r.evaluations;
          return d;
        }, py::arg("V"), py::arg("mask"), py::arg("K"), py::arg("bins"), py::arg("bits"),
        py::arg("method") = "mean", py::arg("alpha") = 0.04, py::arg("delta_k") = 0.001, py::arg("k_max") = 100.0,
        py::arg("guard") = 0.0, py::arg("center_iters") = 0);

  // --- Yang's radial histogram -------------------------------------------------------------------
  m.def("radial_origin", [](VRef V, MRef mask, const std::string& mode) {
          const RadialOrigin o = radial_origin(V, mask, origin_mode(mode));
          return py::make_tuple(Eigen::Vector3d(o.origin), Eigen::Vector3d(o.axis), o.skewness);
        }, py::arg("V"), py::arg("mask"), py::arg("origin_mode") = "axis");

  m.def("radial_counts", [](VRef V, MRef mask, int K, const std::string& mode) {
          check_mask(V, mask);
          const RadialOriginMode om = origin_mode(mode);
          RadialOrigin o;
          RadialCounts h;
          {
            py::gil_scoped_release release;
            o = radial_origin(V, mask, om);
            h = radial_counts(V, mask, K, o.origin);
          }
          return py::make_tuple(std::move(h.counts), Eigen::Vector3d(o.origin), h.rho_min, h.rho_max);
        }, py::arg("V"), py::arg("mask"), py::arg("K"), py::arg("origin_mode") = "axis");

  m.def("radial_histogram", [](Eigen::Ref<const Eigen::VectorXd> rho, int K, MRef mask) {
          RadialHistogram h = radial_histogram(rho, K, mask);
          return py::make_tuple(std::move(h.bin), std::move(h.counts), h.rho_min, h.rho_max);
        }, py::arg("rho"), py::arg("K"), py::arg("mask"));

  m.def("radial_embed", [](VRef V, MRef mask, int K, std::optional<std::vector<int>> pairs, std::vector<int> bits,
                           int n_thr, const std::string& mode, int origin_iters) {
          check_mask(V, mask);
          RadialEmbedOptions o;
          o.first_embeddable = !pairs.has_value();  // None: the i-th embeddable pair takes bit i
          o.n_thr = n_thr;
          o.origin_mode = origin_mode(mode);
          o.origin_iters = origin_iters;
          RadialEmbedResult r;
          {
            py::gil_scoped_release release;
            r = radial_embed(V, mask, K, pairs.value_or(std::vector<int>{}), bits, o);
          }
          py::dict d;
          d["V"] = std::move(r.V);
          d["origin"] = r.origin;
          d["n_mov"] = r.n_mov;
          d["pairs"] = r.pairs;
          d["n_moved"] = r.n_moved;
          d["origin_drift"] = r.drift;
          d["origin_iters"] = r.iterations;
          return d;
        }, py::arg("V"), py::arg("mask"), py::arg("K"), py::arg("pairs"), py::arg("bits"), py::arg("n_thr"),
        py::arg("origin_mode") = "axis", py::arg("origin_iters") = 0);

  // --- §6.4 steganalysis ---------------------------------------------------------------------------
  m.def("gaussian_mixture_2", [](std::vector<double> x, double reg_covar, double tol, int max_iter) {
          const GaussianMixture2 g = gaussian_mixture_2(x, reg_covar, tol, max_iter);
          py::dict d;
          d["weights"] = std::vector<double>{g.weight[0], g.weight[1]};
          d["means"] = std::vector<double>{g.mean[0], g.mean[1]};
          d["variances"] = std::vector<double>{g.var[0], g.var[1]};
          d["labels"] = g.label;
          d["n_iter"] = g.n_iter;
          d["converged"] = g.converged;
          d["lower_bound"] = g.lower_bound;
          d["ok"] = g.ok;
          return d;
        }, py::arg("x"), py::arg("reg_covar") = 1e-6, py::arg("tol") = 1e-3, py::arg("max_iter") = 100);

  m.def("bhattacharyya_distance", &bhattacharyya_distance, py::arg("mean1"), py::arg("var1"), py::arg("mean2"),
        py::arg("var2"));

  m.def("cho_margin_test", [](std::vector<double> mean, std::vector<int> count, int trim, int min_count, int min_bins) {
          if (mean.size() != count.size()) throw MeshError("cho_margin_test: mean and count differ in length");
          const ChoMarginTest t = cho_margin_test(mean, count, trim, min_count, min_bins);
          py::dict d;
          d["ok"] = t.ok;
          d["log_p"] = t.log_p;
          d["hole"] = t.hole;
          d["q"] = t.q;
          d["n_bins"] = t.n_bins;
          d["n_above"] = t.n_above;
          return d;
        }, py::arg("mean"), py::arg("count"), py::arg("trim") = 3, py::arg("min_count") = 5, py::arg("min_bins") = 8);

  m.def("cho_steganalysis", [](VRef V, MRef mask, int K_min, int K_max, double eps, double eps2, int min_bins,
                               double reg_covar, bool fit_em, int trim, int min_count, double false_alarm) {
          check_mask(V, mask);
          ChoSteganalysisOptions o;
          o.K_min = K_min;
          o.K_max = K_max;
          o.eps = eps;
          o.eps2 = eps2;
          o.min_bins = min_bins;
          o.reg_covar = reg_covar;
          o.fit_em = fit_em;
          o.trim = trim;
          o.min_count = min_count;
          o.false_alarm = false_alarm;
          ChoSteganalysisResult r;
          {
            py::gil_scoped_release release;
            r = cho_steganalysis(V, mask, o);
          }
          py::dict d;
          d["K_max_used"] = r.K_max_used;
          d["k_estimate"] = r.K_estimate;
          d["bhattacharyya"] = r.D_max;
          d["D"] = std::move(r.D);
          d["loglik"] = std::move(r.loglik);
          d["min_C"] = r.min_C;
          d["max_Ctilde"] = r.max_Ctilde;
          d["size_C"] = r.size_C;
          d["size_Ctilde"] = r.size_Ctilde;
          d["eq_6_4_16"] = r.eq_6_4_16;
          d["eq_6_4_17"] = r.eq_6_4_17;
          d["balance"] = r.balance;
          d["marked"] = r.marked;
          d["log_p"] = std::move(r.log_p);
          d["hole"] = std::move(r.hole);
          d["n_bins"] = std::move(r.n_bins);
          d["k_margin"] = r.K_margin;
          d["n_tests"] = r.n_tests;
          d["log_p_min"] = r.log_p_min;
          d["log_p_scan"] = r.log_p_scan;
          d["margin"] = r.margin;
          d["q"] = r.q;
          d["margin_bins"] = r.margin_bins;
          d["margin_above"] = r.margin_above;
          d["margin_marked"] = r.margin_marked;
          return d;
        }, py::arg("V"), py::arg("mask"), py::arg("K_min") = 1, py::arg("K_max") = 500, py::arg("eps") = 0.15,
        py::arg("eps2") = 0.03, py::arg("min_bins") = 8, py::arg("reg_covar") = 1e-6, py::arg("fit_em") = true,
        py::arg("trim") = 3, py::arg("min_count") = 5, py::arg("false_alarm") = 0.01);
}

}  // namespace meshmark::python
