#include "meshmark/mesh_info.h"
#include "meshmark/boundary.h"
#include "meshmark/connected_components.h"
#include "meshmark/face_areas.h"
#include "meshmark/manifold.h"
#include "meshmark/triangulate.h"
#include "meshmark/unique_edges.h"
#include "meshmark/validate.h"

#include <vector>

namespace meshmark {

MeshInfo mesh_info(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P) {
  validate_mesh(V, P);
  const Index n = static_cast<Index>(V.rows());
  MeshInfo I;
  I.n_vertices = n;
  I.n_faces = P.n_faces();
  I.n_corners = P.n_corners();
  const EdgeList edges = unique_edges(n, P);
  I.n_edges = edges.E.rows();
  I.n_boundary_edges = boundary_edges(edges).size();
  I.n_boundary_vertices = boundary_vertices(n, edges).size();
  const Components comps = connected_components(n, edges.E);
  I.n_components = comps.count;
  for (Index v = 0; v < n; ++v)
    if (comps.label[v] < 0) ++I.n_unreferenced_vertices;
  const ManifoldReport mr = manifold_report(n, P, edges);
  I.non_manifold_edges = mr.non_manifold_edges;
  I.non_manifold_vertices = mr.non_manifold_vertices;
  I.edge_manifold = mr.edge_manifold();
  I.manifold = mr.manifold();
  I.closed = I.n_boundary_edges == 0;
  I.euler_characteristic = (I.n_vertices - I.n_unreferenced_vertices) - I.n_edges + I.n_faces;
  I.bbox_min = V.colwise().minCoeff().transpose();
  I.bbox_max = V.colwise().maxCoeff().transpose();
  I.bbox_diagonal = (I.bbox_max - I.bbox_min).norm();
  double total = 0;
  for (Eigen::Index e = 0; e < edges.E.rows(); ++e) total += (V.row(edges.E(e, 0)) - V.row(edges.E(e, 1))).norm();
  I.mean_edge_length = edges.E.rows() ? total / static_cast<double>(edges.E.rows()) : 0.0;
  for (Offset f = 0; f < P.n_faces(); ++f) ++I.face_sizes[P.face_size(f)];
  const Triangulation tr = triangulate(V, P);
  const Eigen::VectorXd A = face_areas(V, tr.T);
  I.surface_area = A.sum();
  std::vector<std::uint8_t> nonzero(static_cast<size_t>(P.n_faces()), 0);
  for (Eigen::Index t = 0; t < A.size(); ++t)
    if (A[t] > 0) nonzero[tr.face[t]] = 1;
  for (auto z : nonzero)
    if (!z) ++I.n_degenerate_faces;
  return I;
}

}  // namespace meshmark
