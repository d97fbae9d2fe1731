// Bindings of the §4.3.2 steganography bit layout and orderings, and of the Chao et al. 2009 baseline
// (meshmark.stego): numpy in, numpy out; bit streams as bytes (MSB first).
#include "bindings.h"

#include "meshmark/chao_stego.h"
#include "meshmark/error.h"
#include "meshmark/stego_lsb.h"
#include "meshmark/stego_order.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using namespace arrays;
using namespace pybind11::literals;

StegoPrecision precision(const std::string& s) {
  if (s == "fixed32") return StegoPrecision::Fixed32;
  if (s == "float32") return StegoPrecision::Float32;
  if (s == "float64") return StegoPrecision::Float64;
  throw MeshError("precision must be fixed32, float32 or float64, got '" + s + "'");
}
std::vector<std::uint8_t> to_vec(const py::bytes& b) {
  const std::string s = b;
  return std::vector<std::uint8_t>(s.begin(), s.end());
}
py::bytes to_bytes(const std::vector<std::uint8_t>& v) {
  return py::bytes(reinterpret_cast<const char*>(v.data()), v.size());
}
py::dict frame_dict(const ChaoFrame& f) {
  return py::dict("centroid"_a = f.centroid, "axes"_a = f.axes, "pa"_a = f.pa, "pb"_a = f.pb, "ia"_a = f.ia,
                  "ib"_a = f.ib);
}
ChaoFrame frame_from(const py::dict& d) {
  ChaoFrame f;
  f.centroid = d["centroid"].cast<Eigen::Vector3d>();
  f.axes = d["axes"].cast<Eigen::Matrix3d>();
  f.pa = d["pa"].cast<Eigen::Vector3d>();
  f.pb = d["pb"].cast<Eigen::Vector3d>();
  f.ia = d["ia"].cast<Eigen::Vector3i>();
  f.ib = d["ib"].cast<Eigen::Vector3i>();
  return f;
}
}  // namespace

void bind_stego(py::module_& m) {
  using V3 = Eigen::Vector3d;
  m.def("stego_frame", [](VRef V, const std::string& p) {
          const StegoFrame f = stego_frame(V, precision(p));
          return py::make_tuple(f.E, f.o);
        }, py::arg("V"), py::arg("precision"));
  m.def("stego_extent", [](VRef V) { return stego_extent(V); }, py::arg("V"));
  m.def("stego_snap", [](VRef V, const std::string& p, int E, const V3& o) {
          return stego_snap(V, precision(p), StegoFrame{E, o});
        }, py::arg("V"), py::arg("precision"), py::arg("E"), py::arg("o"));
  m.def("stego_t_range", [](const std::string& p, int E) { return stego_t_range(precision(p), E); },
        py::arg("precision"), py::arg("E"));
  m.def("stego_quantize", [](VRef C, IRef t, const std::string& p, int E, const V3& o) {
          const auto pr = precision(p);
          py::gil_scoped_release r;
          return stego_quantize(C, t, pr, StegoFrame{E, o});
        }, py::arg("C"), py::arg("t"), py::arg("precision"), py::arg("E"), py::arg("o"));
  m.def("stego_clear_lsb", [](VRef C, const std::string& p, int E, const V3& o) {
          const auto pr = precision(p);
          py::gil_scoped_release r;
          return stego_clear_lsb(C, pr, StegoFrame{E, o});
        }, py::arg("C"), py::arg("precision"), py::arg("E"), py::arg("o"));
  m.def("stego_order", [](VRef Q, IRef t, int E, const V3& o, VectorXi indices, VectorXo offsets) {
          const Polygons P = make_polygons(std::move(indices), std::move(offsets));
          StegoOrder so;
          {
            py::gil_scoped_release r;
            so = stego_order(Q, t, E, o, P);
          }
          return py::make_tuple(std::move(so.order), std::move(so.first), so.axis, so.centroid);
        }, py::arg("Q"), py::arg("t"), py::arg("E"), py::arg("o"), py::arg("indices"), py::arg("offsets"));
  m.def("stego_capacity", [](VRef C, IRef t, const std::string& p, int E, const V3& o, IRef order, BRef first) {
          return stego_capacity(C, t, precision(p), StegoFrame{E, o}, order, first);
        }, py::arg("C"), py::arg("t"), py::arg("precision"), py::arg("E"), py::arg("o"), py::arg("order"),
        py::arg("first"));
  m.def("stego_write_bits", [](VRef C, IRef t, const std::string& p, int E, const V3& o, IRef order, BRef first,
                               const py::bytes& bits, std::int64_t nbits) {
          const auto pr = precision(p);
          const auto v = to_vec(bits);
          py::gil_scoped_release r;
          return stego_write_bits(C, t, pr, StegoFrame{E, o}, order, first, v, nbits);
        }, py::arg("C"), py::arg("t"), py::arg("precision"), py::arg("E"), py::arg("o"), py::arg("order"),
        py::arg("first"), py::arg("bits"), py::arg("nbits"));
  m.def("stego_read_bits", [](VRef C, IRef t, const std::string& p, int E, const V3& o, IRef order, BRef first,
                              std::int64_t nbits) {
          const auto pr = precision(p);
          std::vector<std::uint8_t> v;
          {
            py::gil_scoped_release r;
            v = stego_read_bits(C, t, pr, StegoFrame{E, o}, order, first, nbits);
          }
          return to_bytes(v);
        }, py::arg("C"), py::arg("t"), py::arg("precision"), py::arg("E"), py::arg("o"), py::arg("order"),
        py::arg("first"), py::arg("nbits"));
  m.def("stego_lsb_capacity", [](VRef C, const std::string& p, int E, const V3& o, IRef order, BRef first) {
          return stego_lsb_capacity(C, precision(p), StegoFrame{E, o}, first, order);
        }, py::arg("C"), py::arg("precision"), py::arg("E"), py::arg("o"), py::arg("order"), py::arg("first"));
  m.def("stego_write_lsb", [](VRef C, const std::string& p, int E, const V3& o, IRef order, BRef first,
                              const py::bytes& bits, std::int64_t nbits) {
          const auto pr = precision(p);
          const auto v = to_vec(bits);
          py::gil_scoped_release r;
          return stego_write_lsb(C, pr, StegoFrame{E, o}, order, first, v, nbits);
        }, py::arg("C"), py::arg("precision"), py::arg("E"), py::arg("o"), py::arg("order"), py::arg("first"),
        py::arg("bits"), py::arg("nbits"));
  m.def("stego_read_lsb", [](VRef C, const std::string& p, int E, const V3& o, IRef order, BRef first,
                             std::int64_t nbits) {
          const auto pr = precision(p);
          std::vector<std::uint8_t> v;
          {
            py::gil_scoped_release r;
            v = stego_read_lsb(C, pr, StegoFrame{E, o}, order, first, nbits);
          }
          return to_bytes(v);
        }, py::arg("C"), py::arg("precision"), py::arg("E"), py::arg("o"), py::arg("order"), py::arg("first"),
        py::arg("nbits"));

  m.def("chao_frame", [](VRef V) { return frame_dict(chao_frame(V)); }, py::arg("V"));
  m.def("chao_carriers", [](Eigen::Index n, const py::dict& f) { return chao_carriers(n, frame_from(f)); },
        py::arg("n"), py::arg("frame"));
  m.def("chao_embed", [](VRef V, const py::dict& f, const VectorXb& bits, int n_layers, int n_intervals) {
          const ChaoFrame fr = frame_from(f);
          py::gil_scoped_release r;
          return chao_embed(V, fr, bits, n_layers, n_intervals);
        }, py::arg("V"), py::arg("frame"), py::arg("bits"), py::arg("n_layers"), py::arg("n_intervals"));
  m.def("chao_extract", [](VRef V, const py::dict& f, Eigen::Index nbits, int n_layers, int n_intervals) {
          const ChaoFrame fr = frame_from(f);
          py::gil_scoped_release r;
          return chao_extract(V, fr, nbits, n_layers, n_intervals);
        }, py::arg("V"), py::arg("frame"), py::arg("nbits"), py::arg("n_layers"), py::arg("n_intervals"));
}

}  // namespace meshmark::python
