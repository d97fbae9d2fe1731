// meshmark: a summary of a polygon mesh (what `meshmark info` prints).
#pragma once
#include "meshmark/mesh.h"
#include <map>

namespace meshmark {

struct MeshInfo {
  Offset n_vertices = 0, n_faces = 0, n_edges = 0, n_corners = 0;
  Offset n_boundary_edges = 0, n_boundary_vertices = 0;
  Offset n_unreferenced_vertices = 0;
  Offset n_degenerate_faces = 0;      // faces whose triangles all have zero area
  Index n_components = 0;
  Offset non_manifold_edges = 0, non_manifold_vertices = 0;
  bool manifold = false, edge_manifold = false, closed = false;
  Offset euler_characteristic = 0;    // V - E + F over referenced vertices
  Eigen::Vector3d bbox_min, bbox_max; // over all vertices
  double bbox_diagonal = 0, mean_edge_length = 0, surface_area = 0;
  std::map<Index, Offset> face_sizes; // polygon size -> count
};

// Validates the mesh (MeshError on bad input) and computes every field.
MeshInfo mesh_info(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P);

}  // namespace meshmark
