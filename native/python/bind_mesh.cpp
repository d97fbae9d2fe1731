#include "bindings.h"

#include "meshmark/angle_sum.h"
#include "meshmark/error.h"
#include "meshmark/boundary.h"
#include "meshmark/connected_components.h"
#include "meshmark/dihedral_angles.h"
#include "meshmark/face_areas.h"
#include "meshmark/face_normals.h"
#include "meshmark/interior_angles.h"
#include "meshmark/manifold.h"
#include "meshmark/mesh_info.h"
#include "meshmark/pca.h"
#include "meshmark/triangulate.h"
#include "meshmark/unique_edges.h"
#include "meshmark/validate.h"
#include "meshmark/vertex_adjacency.h"
#include "meshmark/weld_vertices.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace meshmark::python {

namespace {
using namespace arrays;  // VRef, TRef, Release (bindings.h)
using ERef = Eigen::Ref<const MatrixX2iR>;

}  // namespace

void bind_mesh(py::module_& m) {
  // Zero-copy: the Python layer passes C-contiguous int32 indices and int64 offsets.
  m.def("validate", [](VRef V, Eigen::Ref<const VectorXi> idx, Eigen::Ref<const VectorXo> off) {
          if (off.size() == 0) throw MeshError("face offsets are empty");
          validate_mesh(V, PolygonsView{idx.data(), idx.size(), off.data(), off.size() - 1});
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"), Release());

  // (n,) uint8: 1 for vertices used by a face.
  m.def("referenced_mask", [](Index n, Eigen::Ref<const VectorXi> idx) {
          VectorXb mask = VectorXb::Zero(n);
          {
            py::gil_scoped_release release;
            for (Eigen::Index c = 0; c < idx.size(); ++c) {
              const Index v = idx[c];
              if (v < 0 || v >= n) throw MeshError("corner " + std::to_string(c) + " refers to vertex " + std::to_string(v) + " out of range");
              mask[v] = 1;
            }
          }
          return mask;
        }, py::arg("n_vertices"), py::arg("indices"));

  m.def("weld_vertices", [](VRef V, Eigen::Ref<const VectorXi> idx, Eigen::Ref<const VectorXo> off) {
          if (off.size() == 0) throw MeshError("face offsets are empty");
          Welded W;
          {
            py::gil_scoped_release release;
            W = weld_vertices(V, PolygonsView{idx.data(), idx.size(), off.data(), off.size() - 1});
          }
          return py::make_tuple(std::move(W.first), std::move(W.map), std::move(W.indices), std::move(W.offsets),
                                std::move(W.face));
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"));

  m.def("unique_edges", [](Index n, VectorXi idx, VectorXo off) {
          EdgeList E = unique_edges(n, make_polygons(std::move(idx), std::move(off)));
          return py::make_tuple(std::move(E.E), std::move(E.face_count));
        }, py::arg("n_vertices"), py::arg("indices"), py::arg("offsets"));

  m.def("vertex_adjacency", [](Index n, ERef E) {
          Adjacency A = vertex_adjacency(n, E);
          return py::make_tuple(std::move(A.ptr), std::move(A.nbr));
        }, py::arg("n_vertices"), py::arg("E"));

  m.def("valence", &valence, py::arg("n_vertices"), py::arg("E"), Release());

  m.def("boundary_edges", [](MatrixX2iR E, VectorXi face_count) { return boundary_edges(EdgeList{std::move(E), std::move(face_count)}); },
        py::arg("E"), py::arg("face_count"), Release());
  m.def("boundary_vertices", [](Index n, MatrixX2iR E, VectorXi face_count) {
          return boundary_vertices(n, EdgeList{std::move(E), std::move(face_count)});
        }, py::arg("n_vertices"), py::arg("E"), py::arg("face_count"), Release());

  m.def("connected_components", [](Index n, ERef E) {
          Components C = connected_components(n, E);
          return py::make_tuple(std::move(C.label), C.count);
        }, py::arg("n_vertices"), py::arg("E"));

  m.def("manifold_report", [](Index n, VectorXi idx, VectorXo off) {
          const Polygons P = make_polygons(std::move(idx), std::move(off));
          const ManifoldReport R = manifold_report(n, P, unique_edges(n, P));
          py::dict d;
          d["non_manifold_edges"] = R.non_manifold_edges;
          d["non_manifold_vertices"] = R.non_manifold_vertices;
          d["edge_manifold"] = R.edge_manifold();
          d["vertex_manifold"] = R.vertex_manifold();
          d["manifold"] = R.manifold();
          return d;
        }, py::arg("n_vertices"), py::arg("indices"), py::arg("offsets"));

  m.def("triangulate", [](VRef V, VectorXi idx, VectorXo off) {
          Triangulation T;
          {
            py::gil_scoped_release release;
            T = triangulate(V, make_polygons(std::move(idx), std::move(off)));
          }
          return py::make_tuple(std::move(T.T), std::move(T.face));
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"));

  m.def("face_normals", &face_normals, py::arg("V"), py::arg("T"), Release());
  m.def("face_areas", &face_areas, py::arg("V"), py::arg("T"), Release());
  m.def("interior_angles", &interior_angles, py::arg("V"), py::arg("T"), Release());
  m.def("angle_sum", &angle_sum, py::arg("V"), py::arg("T"), Release());
  m.def("dihedral_angles", [](VRef V, TRef T) {
          DihedralAngles D = dihedral_angles(V, T);
          return py::make_tuple(std::move(D.edges.E), std::move(D.angle));
        }, py::arg("V"), py::arg("T"));

  m.def("pca", [](VRef V) {
          const PCA p = pca(V);
          py::dict d;
          d["centroid"] = Eigen::Vector3d(p.centroid);
          d["axes"] = Eigen::Matrix3d(p.axes);
          d["eigenvalues"] = Eigen::Vector3d(p.eigenvalues);
          d["skewness"] = Eigen::Vector3d(p.skewness);
          return d;
        }, py::arg("V"));

  m.def("mesh_info", [](VRef V, VectorXi idx, VectorXo off) {
          MeshInfo I;
          {
            py::gil_scoped_release release;
            I = mesh_info(V, make_polygons(std::move(idx), std::move(off)));
          }
          py::dict d;
          d["n_vertices"] = I.n_vertices;
          d["n_faces"] = I.n_faces;
          d["n_edges"] = I.n_edges;
          d["n_corners"] = I.n_corners;
          d["n_boundary_edges"] = I.n_boundary_edges;
          d["n_boundary_vertices"] = I.n_boundary_vertices;
          d["n_unreferenced_vertices"] = I.n_unreferenced_vertices;
          d["n_degenerate_faces"] = I.n_degenerate_faces;
          d["n_components"] = I.n_components;
          d["non_manifold_edges"] = I.non_manifold_edges;
          d["non_manifold_vertices"] = I.non_manifold_vertices;
          d["manifold"] = I.manifold;
          d["edge_manifold"] = I.edge_manifold;
          d["closed"] = I.closed;
          d["euler_characteristic"] = I.euler_characteristic;
          d["bbox_min"] = std::vector<double>{I.bbox_min[0], I.bbox_min[1], I.bbox_min[2]};
          d["bbox_max"] = std::vector<double>{I.bbox_max[0], I.bbox_max[1], I.bbox_max[2]};
          d["bbox_diagonal"] = I.bbox_diagonal;
          d["mean_edge_length"] = I.mean_edge_length;
          d["surface_area"] = I.surface_area;
          py::dict sizes;
          for (const auto& [k, c] : I.face_sizes) sizes[py::str(std::to_string(k))] = c;
          d["face_sizes"] = sizes;
          return d;
        }, py::arg("V"), py::arg("indices"), py::arg("offsets"));
}

}  // namespace meshmark::python
