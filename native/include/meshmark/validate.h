// meshmark: input validation. Every public entry point calls these before touching the data.
#pragma once
#include "meshmark/mesh.h"
#include <Eigen/Core>

namespace meshmark {

// A non-owning view of a face list (e.g. numpy arrays passed from Python without a copy).
struct PolygonsView {
  const Index* indices;
  Offset n_corners;
  const Offset* offsets;  // n_faces + 1 entries
  Offset n_faces;
};

// Throws MeshError if V is empty or holds a NaN/Inf coordinate (the message names the vertex).
void validate_vertices(const Eigen::Ref<const MatrixX3dR>& V);

// Throws MeshError if the face list is empty or malformed: offsets not increasing from 0,
// a face with fewer than 3 corners, an index < 0 or >= n_vertices, or a face that repeats a vertex.
// The message names the first offending face.
void validate_polygons(Index n_vertices, const Polygons& P);
void validate_polygons(Index n_vertices, const PolygonsView& P);

// validate_vertices + validate_polygons.
void validate_mesh(const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P);
void validate_mesh(const Eigen::Ref<const MatrixX3dR>& V, const PolygonsView& P);

}  // namespace meshmark
