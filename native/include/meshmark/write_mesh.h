// meshmark: writing OBJ, OFF, PLY and STL files (through CGAL's stream support).
#pragma once
#include "meshmark/mesh.h"
#include <string>

namespace meshmark {

struct WriteOptions {
  bool binary = true;   // PLY and STL: binary (default) or ASCII; OBJ and OFF are always ASCII
  bool float32 = false; // PLY: store coordinates as float instead of double (STL is always float)
  int precision = 17;   // ASCII: significant digits; 17 makes float64 round trips exact
  int decimals = -1;    // ASCII: if >= 0, fixed notation with this many decimals (OBJ exporters use 6)
};

// Writes V and P; the format comes from the extension. STL stores triangles only: polygons are
// triangulated with triangulate(). Throws MeshError on invalid input or an unwritable path.
void write_mesh(const std::string& path, const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P,
                const WriteOptions& options = WriteOptions());

}  // namespace meshmark
