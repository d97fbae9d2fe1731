// meshmark: reading OBJ, OFF, PLY and STL files (through CGAL's stream support).
#pragma once
#include "meshmark/mesh.h"
#include <string>

namespace meshmark {

struct MeshFile {
  MatrixX3dR V;        // every vertex record of the file, in file order (unreferenced ones included)
  Polygons P;          // faces as stored (polygons kept), in file order
  std::string format;  // "obj", "off", "ply" or "stl"
  bool binary = false; // binary PLY/STL
  bool float32 = false;// the file stores coordinates as 32-bit floats (binary PLY float, STL, binary OFF)
  Offset n_file_faces = 0;    // face records in the file
  Offset n_dropped_faces = 0; // faces dropped because they collapse (repeat a vertex), see read_mesh
};

// Reads the file; the format comes from the extension (case-insensitive). STL triangle corners are
// welded on exactly equal coordinates, numbered in order of first appearance. Throws MeshError with
// the path and what is wrong (missing, empty, unknown format, truncated, malformed line, bad
// index, non-finite coordinate, ...). Never lets another exception escape.
//
// Faces that repeat a vertex: consecutive repeats are merged ((a,b,b,c) -> (a,b,c)); if the face is
// then left with fewer than 3 corners or still repeats a vertex it is dropped and counted in
// n_dropped_faces (drop_collapsed = true, the default; STL triangles whose corners weld together are
// the usual case). With drop_collapsed = false such a face is a MeshError.
MeshFile read_mesh(const std::string& path, bool drop_collapsed = true);

}  // namespace meshmark
