// Bindings of informed tracing (meshmark.watermark.informed): closest points, similarity ICP,
// the low-pass operator and keyed Gaussian fields.
#include "bindings.h"

#include "meshmark/closest_points.h"
#include "meshmark/error.h"
#include "meshmark/keyed_gaussian.h"
#include "meshmark/lowpass_operator.h"
#include "meshmark/similarity_icp.h"
#include "meshmark/triangle_tree.h"

#include <Eigen/LU>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using namespace arrays;
using M4 = Eigen::Matrix<double, 4, 4, Eigen::RowMajor>;

Similarity from4(const M4& A) {  // A = [[s R, t], [0, 1]]
  Similarity S;
  const Eigen::Matrix3d sR = A.topLeftCorner<3, 3>();
  S.s = std::cbrt(sR.determinant());
  if (!(S.s > 0) || !std::isfinite(S.s)) throw MeshError("align: a start transform is not a proper similarity");
  S.R = sR / S.s;
  S.t = A.topRightCorner<3, 1>();
  return S;
}

M4 to4(const Similarity& S) {
  M4 A = M4::Identity();
  A.topLeftCorner<3, 3>() = S.s * S.R;
  A.topRightCorner<3, 1>() = S.t;
  return A;
}
}  // namespace

void bind_tracing(py::module_& m) {
  m.def("closest_points", [](VRef P, VRef V, TRef T) {
          ClosestPoints r;
          {
            py::gil_scoped_release release;
            r = closest_points(P, V, T);
          }
          return py::make_tuple(std::move(r.Q), std::move(r.face), std::move(r.bary), std::move(r.d2));
        }, py::arg("P"), py::arg("V"), py::arg("T"));
  m.def("umeyama", [](VRef P, VRef Q, bool with_scale) { return to4(umeyama(P, Q, with_scale)); },
        py::arg("P"), py::arg("Q"), py::arg("with_scale") = true, Release());
  py::class_<TriangleTree>(m, "TriangleTree",
                           "The bounding-box tree of a triangle set (V, T), built once for closest_points and "
                           "align_similarity")
      .def(py::init<VRef, TRef>(), py::arg("V"), py::arg("T"), Release())
      .def_property_readonly("size", &TriangleTree::size);
  m.def("closest_points", [](VRef P, const TriangleTree& tree) {
          ClosestPoints r;
          {
            py::gil_scoped_release release;
            r = closest_points(P, tree);
          }
          return py::make_tuple(std::move(r.Q), std::move(r.face), std::move(r.bary), std::move(r.d2));
        }, py::arg("P"), py::arg("tree"));
  // One body for both overloads: with the original's tree, or with (V, T) (a tree built for the call).
  auto align = [](VRef P, const TriangleTree* tree, VRef* V, TRef* T, const std::vector<M4>& starts, int coarse,
                  int fine, double trim, bool with_scale, double scale_min, double scale_max, int top, int refine) {
    std::vector<Similarity> S;
    for (const auto& A : starts) S.push_back(from4(A));
    IcpResult r;
    {
      py::gil_scoped_release release;
      r = tree ? align_similarity(P, *tree, S, coarse, fine, trim, with_scale, scale_min, scale_max, top, refine)
               : align_similarity(P, *V, *T, S, coarse, fine, trim, with_scale, scale_min, scale_max, top, refine);
    }
    return py::make_tuple(to4(r.T), r.rms, r.kept_fraction, r.iterations, r.start);
  };
  m.def("align_similarity", [align](VRef P, const TriangleTree& tree, const std::vector<M4>& starts, int coarse,
                                    int fine, double trim, bool with_scale, double scale_min, double scale_max,
                                    int top, int refine) {
          return align(P, &tree, nullptr, nullptr, starts, coarse, fine, trim, with_scale, scale_min, scale_max,
                       top, refine);
        }, py::arg("P"), py::arg("tree"), py::arg("starts"), py::arg("coarse") = 8, py::arg("fine") = 30,
        py::arg("trim") = 0.8, py::arg("with_scale") = true, py::arg("scale_min") = 0.0,
        py::arg("scale_max") = HUGE_VAL, py::arg("top") = 1, py::arg("refine") = 0);
  m.def("align_similarity", [align](VRef P, VRef V, TRef T, const std::vector<M4>& starts, int coarse, int fine,
                                    double trim, bool with_scale, double scale_min, double scale_max, int top,
                                    int refine) {
          return align(P, nullptr, &V, &T, starts, coarse, fine, trim, with_scale, scale_min, scale_max, top,
                       refine);
        }, py::arg("P"), py::arg("V"), py::arg("T"), py::arg("starts"), py::arg("coarse") = 8, py::arg("fine") = 30,
        py::arg("trim") = 0.8, py::arg("with_scale") = true, py::arg("scale_min") = 0.0,
        py::arg("scale_max") = HUGE_VAL, py::arg("top") = 1, py::arg("refine") = 0);
  py::class_<LowpassOperator>(m, "LowpassOperator")
      .def(py::init<VRef, TRef, double, int>(), py::arg("V"), py::arg("T"), py::arg("t"), py::arg("k"), Release())
      .def("apply", &LowpassOperator::apply, py::arg("W"), Release())
      .def("apply_transpose", &LowpassOperator::apply_transpose, py::arg("R"), Release())
      .def_property_readonly("mass", &LowpassOperator::mass)
      .def_property_readonly("size", &LowpassOperator::size);
  m.def("keyed_gaussians", &keyed_gaussians, py::arg("seeds"), py::arg("n"), Release());
  m.def("keyed_gaussian_dots", &keyed_gaussian_dots, py::arg("u"), py::arg("seeds"), Release());
}

}  // namespace meshmark::python
