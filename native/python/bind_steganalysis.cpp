#include "bindings.h"

#include "meshmark/feature_frame.h"
#include "meshmark/feature_statistics.h"
#include "meshmark/lfs76_features.h"
#include "meshmark/lfs76s_features.h"
#include "meshmark/nvt36_features.h"
#include "meshmark/nvt36s_features.h"
#include "meshmark/pca_min_corner_normalize.h"
#include "meshmark/rusinkiewicz_curvatures.h"
#include "meshmark/unit_cube_normalize.h"
#include "meshmark/yang208_features.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

void bind_steganalysis(py::module_& m) {
  using VRef = Eigen::Ref<const MatrixX3dR>;
  using TRef = Eigen::Ref<const MatrixX3iR>;
  using XRef = Eigen::Ref<const Eigen::VectorXd>;
  m.def("yang208_features", [](VRef V, TRef T) {
          py::gil_scoped_release release;
          return yang208_features(V, T);
        }, py::arg("V"), py::arg("T"));
  m.def("lfs76_features", [](VRef V, TRef T, double dt, double t_max) {
          py::gil_scoped_release release;
          return lfs76_features(V, T, dt, t_max);
        }, py::arg("V"), py::arg("T"), py::arg("dt") = 0.3, py::arg("t_max") = 3.0);
  m.def("lfs76s_features", [](VRef V, TRef T, double dt, double t_max) {
          py::gil_scoped_release release;
          return lfs76s_features(V, T, dt, t_max);
        }, py::arg("V"), py::arg("T"), py::arg("dt") = 0.3, py::arg("t_max") = 3.0);
  m.def("nvt36_features", [](VRef V, TRef T) {
          py::gil_scoped_release release;
          return nvt36_features(V, T);
        }, py::arg("V"), py::arg("T"));
  m.def("nvt36s_features", [](VRef V, TRef T) {
          py::gil_scoped_release release;
          return nvt36s_features(V, T);
        }, py::arg("V"), py::arg("T"));
  m.def("pca_min_corner_normalize", [](VRef V) { return pca_min_corner_normalize(V); }, py::arg("V"));
  m.def("rusinkiewicz_curvatures", [](VRef V, TRef T) {
          const PrincipalCurvatures k = rusinkiewicz_curvatures(V, T);
          return py::make_tuple(k.k1, k.k2);
        }, py::arg("V"), py::arg("T"));
  m.def("unit_cube_normalize", [](VRef V, Eigen::Ref<const VectorXb> mask) { return unit_cube_normalize(V, mask); },
        py::arg("V"), py::arg("mask"));
  m.def("feature_moments4", [](XRef x) { return Eigen::Vector4d(moments4(x)); }, py::arg("x"));
  m.def("feature_log_moments", [](XRef x, double floor) { return Eigen::Vector4d(log_moments(x, floor)); },
        py::arg("x"), py::arg("floor"));
  m.def("feature_moments4_regularized", [](XRef x, double s0) { return Eigen::Vector4d(moments4_regularized(x, s0)); },
        py::arg("x"), py::arg("s0") = kMomentVarianceFloor);
  m.def("feature_floored_log_moments", [](XRef f, XRef b, double cap) {
          NoisyVector v;
          for (Eigen::Index i = 0; i < f.size(); ++i) v.push(f[i], b[i]);
          return Eigen::Vector4d(floored_log_moments(v, cap));
        }, py::arg("f"), py::arg("bound"), py::arg("cap"));
  m.attr("FEATURE_STORAGE_UNIT") = kStorageUnit;
  m.attr("FEATURE_NOISE_FACTOR") = kNoiseFactor;
  m.def("feature_frame", [](VRef V, Eigen::Ref<const VectorXb> mask) {
          const FeatureFrame fr = feature_frame(V, mask);
          return py::make_tuple(fr.X, std::vector<int>(fr.group.begin(), fr.group.end()), fr.lambda);
        }, py::arg("V"), py::arg("mask"));
  m.def("feature_fd_bins", [](XRef x) { return fd_bins_exact(x); }, py::arg("x"));
  m.def("feature_histogram_moments", [](XRef x) { return Eigen::Vector4d(histogram_moments(x)); }, py::arg("x"));
}

}  // namespace meshmark::python
