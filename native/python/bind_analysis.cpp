// Bindings of the distortion analysis of thesis ch. 3-5 (meshmark.analysis): numpy in, numpy out.
#include "bindings.h"

#include "meshmark/curvature_degradation.h"
#include "meshmark/error.h"
#include "meshmark/gaussian_curvature.h"
#include "meshmark/normal_angle_expectation.h"
#include "meshmark/normal_degradation_sweep.h"
#include "meshmark/quantization_level.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <string>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using namespace arrays;
using namespace pybind11::literals;

NoiseBound parse_bound(const std::string& b) {
  if (b == "min") return NoiseBound::Min;
  if (b == "appr") return NoiseBound::Appr;
  if (b == "max") return NoiseBound::Max;
  throw MeshError("unknown bound '" + b + "' (expected min, appr or max)");
}

LevelFormula parse_formula(const std::string& f) {
  if (f == "auto") return LevelFormula::Auto;
  if (f == "linear") return LevelFormula::Linear;
  if (f == "exact") return LevelFormula::Exact;
  throw MeshError("unknown formula '" + f + "' (expected auto, linear or exact)");
}
}  // namespace

void bind_analysis(py::module_& m) {
  m.def("expected_normal_angle", [](const Eigen::Ref<const Eigen::VectorXd>& r) {
          Eigen::VectorXd out(r.size());
          for (Eigen::Index i = 0; i < r.size(); ++i) out[i] = expected_normal_angle(r[i]);
          return out;
        }, py::arg("r"), Release());
  m.def("normal_noise_monte_carlo", [](const Eigen::Matrix3d& P, const Eigen::Vector3i& noisy, double l,
                                       std::int64_t n, std::uint64_t seed) {
          MonteCarloAngle r;
          {
            py::gil_scoped_release release;
            r = normal_noise_monte_carlo(P, noisy, l, n, seed);
          }
          return py::make_tuple(r.mean, r.stderr_, r.n);
        }, py::arg("P"), py::arg("noisy"), py::arg("l"), py::arg("n"), py::arg("seed"));
  m.def("triangle_heights", [](VRef V, TRef T) {
          TriangleHeights H;
          {
            py::gil_scoped_release release;
            H = triangle_heights(V, T);
          }
          Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> h(H.inv_h.rows(), 3);
          for (Eigen::Index f = 0; f < h.rows(); ++f)  // heights ascending (0 for unusable triangles)
            for (int k = 0; k < 3; ++k) h(f, k) = H.usable[f] ? 1.0 / H.inv_h(f, k) : 0.0;
          return py::make_tuple(std::move(h), std::move(H.usable));
        }, py::arg("V"), py::arg("T"));
  m.def("mesh_normal_expectation", [](VRef V, TRef T, const Eigen::Ref<const Eigen::VectorXd>& l,
                                      const std::string& bound, bool exact, double eta) {
          const NoiseBound b = parse_bound(bound);
          py::gil_scoped_release release;
          const TriangleHeights H = triangle_heights(V, T);
          if (H.n_usable == 0) throw MeshError("the mesh has no usable triangle (every triangle has zero area)");
          Eigen::VectorXd out(l.size());
          for (Eigen::Index i = 0; i < l.size(); ++i) out[i] = mesh_normal_expectation(H, l[i], b, exact, eta);
          return out;
        }, py::arg("V"), py::arg("T"), py::arg("l"), py::arg("bound"), py::arg("exact"), py::arg("eta"));
  m.def("quantization_level", [](VRef V, TRef T, double eps, const std::string& bound, const std::string& formula,
                                 double eta, double switch_tol) {
          const NoiseBound b = parse_bound(bound);
          const LevelFormula f = parse_formula(formula);
          QuantizationLevel q;
          {
            py::gil_scoped_release release;
            q = quantization_level(V, T, eps, b, f, eta, switch_tol);
          }
          return py::dict("level"_a = q.level, "level_unclamped"_a = q.level_unclamped,
                          "level_linear"_a = q.level_linear, "used_exact"_a = q.used_exact, "e_linear"_a = q.e_linear,
                          "e_exact"_a = q.e_exact, "e_level"_a = q.e_level, "cube"_a = q.cube,
                          "n_triangles"_a = q.n_triangles);
        }, py::arg("V"), py::arg("T"), py::arg("eps"), py::arg("bound"), py::arg("formula"), py::arg("eta"),
        py::arg("switch_tol"));
  m.def("adaptive_levels", [](VRef V, TRef T, const Eigen::Ref<const Eigen::VectorXd>& kappa, double eps0,
                              double alpha, double mu, double sigma, double eta) {
          AdaptiveLevels a;
          {
            py::gil_scoped_release release;
            a = adaptive_levels(V, T, kappa, eps0, alpha, mu, sigma, eta);
          }
          return py::make_tuple(std::move(a.vertex_level), std::move(a.triangle_level),
                                std::move(a.triangle_tolerance));
        }, py::arg("V"), py::arg("T"), py::arg("kappa"), py::arg("eps0"), py::arg("alpha"), py::arg("mu"),
        py::arg("sigma"), py::arg("eta"));
  // level-only fast paths: None where the general function must decide (quantization_level.h)
  m.def("quantization_level_only", [](VRef V, TRef T, double eps, const std::string& bound,
                                        const std::string& formula, double eta, double switch_tol) {
          const NoiseBound b = parse_bound(bound);
          const LevelFormula f = parse_formula(formula);
          py::gil_scoped_release release;
          return quantization_level_only(V, T, eps, b, f, eta, switch_tol);
        }, py::arg("V"), py::arg("T"), py::arg("eps"), py::arg("bound"), py::arg("formula"), py::arg("eta"),
        py::arg("switch_tol"));
  m.def("uniform_adaptive_levels", [](VRef V, TRef T, double eps0, double eta) {
          py::gil_scoped_release release;
          return uniform_adaptive_levels(V, T, eps0, eta);
        }, py::arg("V"), py::arg("T"), py::arg("eps0"), py::arg("eta"));
  m.def("gaussian_curvature", [](VRef V, TRef T) {
          GaussianCurvature g;
          {
            py::gil_scoped_release release;
            g = gaussian_curvature(V, T);
          }
          return py::make_tuple(std::move(g.kappa), std::move(g.interior), std::move(g.boundary));
        }, py::arg("V"), py::arg("T"));
  m.def("normal_degradation_sweep", [](VRef V, TRef T, const Eigen::Ref<const VectorXi>& t, std::uint64_t seed,
                                       int repeats, double mu, double sigma) {
          NormalDegradationSweep r;
          {
            py::gil_scoped_release release;
            r = normal_degradation_sweep(V, T, t, seed, repeats, mu, sigma);
          }
          return py::make_tuple(std::move(r.mean), std::move(r.variance), std::move(r.excluded));
        }, py::arg("V"), py::arg("T"), py::arg("t"), py::arg("seed"), py::arg("repeats"), py::arg("mu") = 0.0,
        py::arg("sigma") = 3.5);
  m.def("sweep_seed", &sweep_seed, py::arg("seed"), py::arg("t"), py::arg("r"));
  m.def("mean_face_normals", &mean_face_normals, py::arg("V"), py::arg("T"), Release());
  m.def("curvature_degradation", [](VRef V, TRef T, const Eigen::Ref<const VectorXi>& t, const std::string& direction,
                                    const Eigen::Ref<const VectorXb>& moved, const Eigen::Ref<const VectorXb>& measured,
                                    double scale, int repeats, std::uint64_t seed) {
          Displacement d;
          if (direction == "normal") d = Displacement::Normal;
          else if (direction == "tangential") d = Displacement::Tangential;
          else if (direction == "random") d = Displacement::Random;
          else throw MeshError("unknown direction '" + direction + "' (expected normal, tangential or random)");
          py::gil_scoped_release release;
          return curvature_degradation(V, T, t, d, moved, measured, scale, repeats, seed);
        }, py::arg("V"), py::arg("T"), py::arg("t"), py::arg("direction"), py::arg("moved"), py::arg("measured"),
        py::arg("scale"), py::arg("repeats"), py::arg("seed"));
}

}  // namespace meshmark::python
