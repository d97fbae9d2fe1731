// Bindings of the distortion metrics (meshmark.metrics): numpy in, numpy out.
#include "bindings.h"

#include "meshmark/error.h"
#include "meshmark/normal_degradation.h"
#include "meshmark/surface_distance.h"
#include "meshmark/hausdorff_distance.h"
#include "meshmark/vertex_rmse.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using namespace arrays;  // VRef, TRef, Release (bindings.h)

py::dict as_dict(const OneSidedDistance& d) {
  py::dict r;
  r["max"] = d.max;
  r["mean"] = d.mean;
  r["rms"] = d.rms;
  r["min"] = d.min;
  r["n_samples"] = d.n_samples;
  return r;
}
}  // namespace

void bind_metrics(py::module_& m) {
  m.def("vertex_rmse", &vertex_rmse, py::arg("V"), py::arg("V2"), Release());
  m.def("min_dihedral_angles_deg", &min_dihedral_angles_deg, py::arg("V"), py::arg("T"), Release());
  m.def("normal_degradation", [](VRef V, VRef V2, TRef T, const std::string& weighting, double mu, double sigma) {
          NormalWeighting w;
          if (weighting == "mean") w = NormalWeighting::Mean;
          else if (weighting == "area") w = NormalWeighting::Area;
          else if (weighting == "dihedral") w = NormalWeighting::Dihedral;
          else throw MeshError("unknown weighting '" + weighting + "' (expected mean, area or dihedral)");
          NormalDegradation r;
          {
            py::gil_scoped_release release;
            r = normal_degradation(V, V2, T, w, mu, sigma);
          }
          return py::make_tuple(r.value, std::move(r.angle), std::move(r.weight), r.n_excluded);
        }, py::arg("V"), py::arg("V2"), py::arg("T"), py::arg("weighting"), py::arg("mu") = 0.0, py::arg("sigma") = 3.5);
  m.def("sample_surface", [](VRef V, TRef T, Eigen::Index n, std::uint64_t seed) {
          VectorXi face;
          MatrixX3dR P;
          {
            py::gil_scoped_release release;
            P = sample_surface(V, T, n, seed, &face);
          }
          return py::make_tuple(std::move(P), std::move(face));
        }, py::arg("V"), py::arg("T"), py::arg("n"), py::arg("seed"));
  m.def("point_mesh_distance", [](VRef P, VRef V, TRef T) {
          VectorXi face;
          Eigen::VectorXd d;
          {
            py::gil_scoped_release release;
            d = point_mesh_distance(P, V, T, &face);
          }
          return py::make_tuple(std::move(d), std::move(face));
        }, py::arg("P"), py::arg("V"), py::arg("T"));
  m.def("one_sided_distance", [](VRef VA, TRef TA, VRef VB, TRef TB, Eigen::Index n, bool vertices, std::uint64_t seed) {
          OneSidedDistance d;
          {
            py::gil_scoped_release release;
            d = one_sided_distance(VA, TA, VB, TB, n, vertices, seed);
          }
          return as_dict(d);
        }, py::arg("VA"), py::arg("TA"), py::arg("VB"), py::arg("TB"), py::arg("n_samples"), py::arg("include_vertices"),
        py::arg("seed"));
  m.def("hausdorff_distance", [](VRef VA, TRef TA, VRef VB, TRef TB, double rel_tol, double abs_tol,
                                  Eigen::Index max_queries) {
          HausdorffBound h;
          {
            py::gil_scoped_release release;
            h = hausdorff_distance(VA, TA, VB, TB, rel_tol, abs_tol, max_queries);
          }
          py::dict d;
          d["lower"] = h.lower;
          d["upper"] = h.upper;
          d["n_queries"] = h.n_queries;
          d["converged"] = h.converged;
          return d;
        }, py::arg("VA"), py::arg("TA"), py::arg("VB"), py::arg("TB"), py::arg("rel_tol") = 1e-3, py::arg("abs_tol") = 0.0,
        py::arg("max_queries") = 0);
}

}  // namespace meshmark::python
