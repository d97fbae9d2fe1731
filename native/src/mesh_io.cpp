// Writing mesh files through CGAL's stream support (CGAL/IO). Reading is in read_mesh.cpp and the
// per-format readers (read_obj.cpp, read_off.cpp, read_ply.cpp; read_stl.cpp, the only other
// translation unit with a CGAL IO header).
#include "file_extension.h"
#include "meshmark/error.h"
#include "meshmark/printable.h"
#include "meshmark/triangulate.h"
#include "meshmark/validate.h"
#include "meshmark/write_mesh.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <cstdio>
#include <unistd.h>
#include <vector>

namespace meshmark {

namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;
using PointF = CGAL::Simple_cartesian<float>::Point_3;
using Polygon = std::vector<std::size_t>;

bool write_stream(std::ostream& os, const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P, const WriteOptions& options,
                  const std::string& ext, bool binary) {
  int precision = options.precision;
  if (options.decimals >= 0) {
    os << std::fixed;
    precision = options.decimals;
  }
  std::vector<Point> pts(static_cast<size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) pts[i] = Point(V(i, 0), V(i, 1), V(i, 2));
  std::vector<Polygon> polys(static_cast<size_t>(P.n_faces()));
  for (Offset f = 0; f < P.n_faces(); ++f)
    polys[f].assign(P.indices.data() + P.offsets[f], P.indices.data() + P.offsets[f + 1]);
  const auto np = CGAL::parameters::stream_precision(precision).use_binary_mode(binary);
  CGAL::IO::set_mode(os, binary ? CGAL::IO::BINARY : CGAL::IO::ASCII);
  bool ok = false;
  if (ext == "obj") ok = CGAL::IO::write_OBJ(os, pts, polys, np);
  else if (ext == "off") ok = CGAL::IO::write_OFF(os, pts, polys, np);
  else if (ext == "ply") {
    if (options.float32) {
      std::vector<PointF> ptsf(pts.size());
      for (size_t i = 0; i < pts.size(); ++i)
        ptsf[i] = PointF(static_cast<float>(pts[i].x()), static_cast<float>(pts[i].y()), static_cast<float>(pts[i].z()));
      ok = CGAL::IO::write_PLY(os, ptsf, polys, CGAL::parameters::stream_precision(options.decimals >= 0 ? precision : 9));
    } else {
      ok = CGAL::IO::write_PLY(os, pts, polys, np);
    }
  } else {
    const Triangulation tr = triangulate(V, P);
    std::vector<std::array<std::size_t, 3>> tris(static_cast<size_t>(tr.T.rows()));
    for (Eigen::Index t = 0; t < tr.T.rows(); ++t) tris[t] = {static_cast<std::size_t>(tr.T(t, 0)), static_cast<std::size_t>(tr.T(t, 1)), static_cast<std::size_t>(tr.T(t, 2))};
    ok = CGAL::IO::write_STL(os, pts, tris, np);
  }
  return ok;
}

// The temporary file write_mesh writes first: in the target's folder (so the rename is atomic) and
// with the target's extension, e.g. "dir/.out.obj.meshmark-tmp-1234.obj".
std::string temp_path(const std::string& path, const std::string& ext) {
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  return dir + "." + base + ".meshmark-tmp-" + std::to_string(static_cast<long long>(getpid())) + "." + ext;
}
}  // namespace

// Written to a temporary file in the same folder, then renamed over `path`: a failed write leaves
// neither a partial file nor a changed old one.
void write_mesh(const std::string& path, const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P,
                const WriteOptions& options) {
  validate_mesh(V, P);
  const std::string shown = printable(path, 400);
  const std::string ext = detail::file_extension(path);
  if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
    throw MeshError("cannot write '" + shown + "': unsupported format '" + (ext.empty() ? std::string("(no extension)") : "." + printable(ext, 20)) +
                    "' (supported: .obj .off .ply .stl)");
  const bool binary = options.binary && (ext == "ply" || ext == "stl");
  const std::string tmp = temp_path(path, ext);
  bool ok = false;
  {
    std::ofstream os(tmp, binary ? std::ios::binary : std::ios::out);
    if (!os) throw MeshError("cannot write '" + shown + "': " + std::strerror(errno));
    try {
      ok = write_stream(os, V, P, options, ext, binary);
      os.flush();
      ok = ok && static_cast<bool>(os);
    } catch (...) {
      os.close();
      std::remove(tmp.c_str());
      throw;
    }
  }
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw MeshError("cannot write '" + shown + "': " + (ok ? std::string(std::strerror(err)) : "write failed (disk full or no permission?)"));
  }
}

}  // namespace meshmark
