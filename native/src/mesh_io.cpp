// Reading and writing mesh files through CGAL's stream support (CGAL/IO). This is the only
// translation unit that includes CGAL's IO headers. Files are pre-checked here only to give precise
// messages (header counts, truncation); the parsing itself is CGAL's.
#include "meshmark/error.h"
#include "meshmark/read_mesh.h"
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
#include <sys/stat.h>
#include <vector>

namespace meshmark {

namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;
using PointF = CGAL::Simple_cartesian<float>::Point_3;
using Polygon = std::vector<std::size_t>;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw MeshError("cannot read '" + path + "': " + what);
}

std::string extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

long long file_size(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return -1;
  if (!S_ISREG(st.st_mode)) return -2;
  return static_cast<long long>(st.st_size);
}

// --- PLY header (read only to report counts and detect truncation) ---------------------------
struct PlyHeader {
  std::string format;
  long long n_vertices = -1, n_faces = -1;
  long long header_bytes = 0;
  long long vertex_record_bytes = 0;  // bytes per vertex record (binary, fixed-size properties)
  long long face_min_bytes = 0;       // smallest possible face record (a list of 3 indices)
  bool vertex_fixed = true;
  bool float32 = false;
};

int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

PlyHeader read_ply_header(const std::string& path, std::istream& is) {
  PlyHeader h;
  std::string line, current;
  if (!std::getline(is, line) || line.substr(0, 3) != "ply") fail(path, "not a PLY file (the first line is not 'ply')");
  h.header_bytes += static_cast<long long>(line.size()) + 1;
  bool ended = false;
  int lines = 1;
  while (std::getline(is, line)) {
    ++lines;
    h.header_bytes += static_cast<long long>(line.size()) + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "format") ls >> h.format;
    else if (kw == "element") {
      long long count = -1;
      ls >> current >> count;
      if (count < 0) fail(path, "PLY header line " + std::to_string(lines) + ": bad element count: '" + line + "'");
      if (current == "vertex") h.n_vertices = count;
      if (current == "face") h.n_faces = count;
    } else if (kw == "property" && current == "face") {
      std::string type, ct, it;
      ls >> type;
      if (type == "list") {
        ls >> ct >> it;
        h.face_min_bytes += ply_type_size(ct) + 3 * ply_type_size(it);
      } else {
        h.face_min_bytes += ply_type_size(type);
      }
    } else if (kw == "property" && current == "vertex") {
      std::string type, name;
      ls >> type;
      if (type == "list") h.vertex_fixed = false;
      else {
        ls >> name;
        h.vertex_record_bytes += ply_type_size(type);
        if ((name == "x" || name == "y" || name == "z") && (type == "float" || type == "float32")) h.float32 = true;
      }
    } else if (kw == "end_header") {
      ended = true;
      break;
    }
    if (lines > 10000) break;
  }
  if (!ended) fail(path, "PLY header has no 'end_header' line (truncated or not a PLY file)");
  if (h.format != "ascii" && h.format != "binary_little_endian" && h.format != "binary_big_endian")
    fail(path, "unknown PLY format '" + h.format + "' (expected ascii, binary_little_endian or binary_big_endian)");
  if (h.n_vertices < 0) fail(path, "PLY header declares no 'vertex' element");
  if (h.n_faces < 0) fail(path, "PLY header declares no 'face' element");
  return h;
}

// --- OFF header --------------------------------------------------------------------------------
void read_off_counts(const std::string& path, std::istream& is, long long& nv, long long& nf) {
  std::string tok;
  std::vector<long long> nums;
  bool magic = false;
  std::string line;
  while (nums.size() < 3 && std::getline(is, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream ls(line);
    while (ls >> tok) {
      if (!magic && nums.empty() && tok.find("OFF") != std::string::npos) {
        magic = true;
        continue;
      }
      char* end = nullptr;
      const long long v = std::strtoll(tok.c_str(), &end, 10);
      if (*end != 0) fail(path, "OFF header: expected vertex/face/edge counts, found '" + tok + "'");
      nums.push_back(v);
    }
  }
  if (nums.size() < 2) fail(path, "OFF header has no vertex and face counts (empty or truncated file)");
  nv = nums[0];
  nf = nums[1];
  if (nv < 0 || nf < 0) fail(path, "OFF header has negative counts");
}

// --- OBJ diagnosis: find the first line CGAL's reader would refuse ------------------------------
std::string diagnose_obj(const std::string& path) {
  std::ifstream is(path);
  std::string line;
  int lineno = 0;
  static const char* known[] = {"v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s", "usemtl", "mtllib", "#"};
  long n_vertices = 0, worst = 0;
  int worst_line = 0;
  while (std::getline(is, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string kw;
    if (!(ls >> kw)) continue;
    if (kw[0] == '#') continue;
    bool ok = false;
    for (const char* k : known) ok = ok || kw == k;
    if (kw == "l" || kw == "p")
      return "line " + std::to_string(lineno) + ": OBJ '" + kw + "' (line/point) elements are not supported";
    if (!ok && kw.size() > 0) {
      // CGAL accepts a few more rarely used statements; report only clearly unknown ones.
      if (kw == "bevel" || kw == "lod" || kw == "cstype" || kw == "deg" || kw == "curv" || kw == "surf") continue;
      return "line " + std::to_string(lineno) + ": unrecognized OBJ statement '" + kw + "'";
    }
    if (kw == "v") {
      ++n_vertices;
      std::string tok;
      for (int k = 0; k < 3; ++k) {
        if (!(ls >> tok)) return "line " + std::to_string(lineno) + ": vertex has fewer than 3 coordinates";
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(tok.c_str(), &end);
        if (*end != 0) return "line " + std::to_string(lineno) + ": '" + tok + "' is not a number";
        if (!std::isfinite(x)) return "line " + std::to_string(lineno) + ": vertex coordinate '" + tok + "' is not finite";
      }
    }
    if (kw == "f") {
      std::string tok;
      while (ls >> tok) {
        char* end = nullptr;
        const long v = std::strtol(tok.c_str(), &end, 10);
        if (end == tok.c_str()) return "line " + std::to_string(lineno) + ": face index '" + tok + "' is not an integer";
        if (v == 0) return "line " + std::to_string(lineno) + ": face index 0 (OBJ indices start at 1)";
        const long absolute = v > 0 ? v : n_vertices + v + 1;
        if ((absolute > worst || absolute < 1) && worst_line == 0) {
          if (absolute < 1 || absolute > n_vertices) {
            worst = absolute;
            worst_line = lineno;
          }
        }
      }
    }
  }
  if (worst_line)
    return "line " + std::to_string(worst_line) + ": face index " + std::to_string(worst) +
           " refers to a vertex that does not exist (" + std::to_string(n_vertices) + " vertices in the file)";
  return "";
}

template <class PointT>
void fill_mesh(MeshFile& out, const std::vector<PointT>& pts, const std::vector<Polygon>& polys) {
  out.V.resize(static_cast<Eigen::Index>(pts.size()), 3);
  for (size_t i = 0; i < pts.size(); ++i) {
    out.V(i, 0) = pts[i].x();
    out.V(i, 1) = pts[i].y();
    out.V(i, 2) = pts[i].z();
  }
  size_t corners = 0;
  for (const auto& p : polys) corners += p.size();
  out.P.indices.resize(static_cast<Eigen::Index>(corners));
  out.P.offsets.resize(static_cast<Eigen::Index>(polys.size()) + 1);
  out.P.offsets[0] = 0;
  Offset c = 0;
  for (size_t f = 0; f < polys.size(); ++f) {
    for (std::size_t v : polys[f]) {
      // Indices beyond int32 (or wrapped negatives from the readers) are reported by validation.
      out.P.indices[c++] = v > static_cast<std::size_t>(INT32_MAX) ? -1 : static_cast<Index>(v);
    }
    out.P.offsets[static_cast<Eigen::Index>(f) + 1] = c;
  }
}


// Binary OFF ("OFF BINARY"): counts, float32 coordinates and int32 face records. The format is
// big-endian by its definition, but pmp-library and others write it little-endian; CGAL reads only
// the former (and runs out of memory on the latter), so this small reader takes the endianness for
// which the counts fit the file size.
template <class T>
T load(const unsigned char* p, bool big) {
  unsigned char b[sizeof(T)];
  for (size_t i = 0; i < sizeof(T); ++i) b[i] = big ? p[sizeof(T) - 1 - i] : p[i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

void read_binary_off(const std::string& path, std::istream& is, long long size, std::vector<Point>& pts,
                     std::vector<Polygon>& polys, MeshFile& out) {
  const std::streamoff start = is.tellg();
  std::vector<unsigned char> buf(static_cast<size_t>(size - start));
  is.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
  if (buf.size() < 12) fail(path, "truncated binary OFF: no vertex/face counts after the header");
  const long long body = static_cast<long long>(buf.size());
  bool big = true;
  std::int32_t nv = load<std::int32_t>(&buf[0], true), nf = load<std::int32_t>(&buf[4], true);
  auto fits = [&](std::int32_t a, std::int32_t b) { return a >= 0 && b >= 0 && 12 + 12LL * a + 16LL * b <= body; };
  if (!fits(nv, nf)) {
    big = false;
    nv = load<std::int32_t>(&buf[0], false);
    nf = load<std::int32_t>(&buf[4], false);
    if (!fits(nv, nf))
      fail(path, "truncated or malformed binary OFF: the vertex/face counts do not fit the file size");
  }
  out.binary = true;
  out.float32 = true;
  size_t p = 12;
  pts.reserve(static_cast<size_t>(nv));
  for (std::int32_t i = 0; i < nv; ++i, p += 12)
    pts.emplace_back(load<float>(&buf[p], big), load<float>(&buf[p + 4], big), load<float>(&buf[p + 8], big));
  polys.resize(static_cast<size_t>(nf));
  for (std::int32_t f = 0; f < nf; ++f) {
    if (p + 4 > buf.size()) fail(path, "truncated binary OFF: face " + std::to_string(f) + " is cut off");
    const std::int32_t k = load<std::int32_t>(&buf[p], big);
    p += 4;
    if (k < 0 || p + 4ULL * static_cast<size_t>(k) > buf.size())
      fail(path, "truncated or malformed binary OFF: face " + std::to_string(f) + " declares " + std::to_string(k) + " corners");
    polys[f].resize(static_cast<size_t>(k));
    for (std::int32_t j = 0; j < k; ++j, p += 4) {
      const std::int32_t v = load<std::int32_t>(&buf[p], big);
      polys[f][j] = v < 0 ? static_cast<std::size_t>(-1) : static_cast<std::size_t>(v);
    }
  }
}

// Faces that repeat a vertex: consecutive repeats are merged ((a,b,b,c) -> (a,b,c)); a face left
// with fewer than 3 corners, or still repeating a vertex, is dropped when drop_collapsed is set
// (STL triangles whose corners weld together are the usual case). Then the mesh is validated.
void finish(const std::string& path, MeshFile& out, bool drop_collapsed) {
  Polygons& P = out.P;
  const Offset m = P.n_faces();
  out.n_file_faces = m;
  bool any_repeat = false;  // fast path: most files have no face that repeats a vertex
  for (Offset f = 0; f < m && !any_repeat; ++f)
    for (Offset a = P.offsets[f]; a < P.offsets[f + 1] && !any_repeat; ++a)
      for (Offset d = a + 1; d < P.offsets[f + 1]; ++d)
        if (P.indices[a] == P.indices[d]) {
          any_repeat = true;
          break;
        }
  if (drop_collapsed && any_repeat) {
    VectorXi idx(P.indices.size());
    VectorXo off(m + 1);
    off[0] = 0;
    Offset c = 0, kept = 0;
    for (Offset f = 0; f < m; ++f) {
      const Offset b = P.offsets[f], e = P.offsets[f + 1];
      const Offset start = c;
      for (Offset j = b; j < e; ++j) {
        const Index v = P.indices[j];
        if (c > start && idx[c - 1] == v) continue;
        idx[c++] = v;
      }
      while (c - start > 1 && idx[c - 1] == idx[start]) --c;
      bool ok = c - start >= 3;
      for (Offset a = start; ok && a < c; ++a)
        for (Offset d = a + 1; ok && d < c; ++d) ok = idx[a] != idx[d];
      if (!ok) {
        c = start;
        continue;
      }
      off[++kept] = c;
    }
    out.n_dropped_faces = m - kept;
    if (out.n_dropped_faces > 0 || c != P.n_corners()) {
      P.indices = idx.head(c);
      P.offsets = off.head(kept + 1);
    }
  }
  try {
    validate_mesh(out.V, out.P);
  } catch (const MeshError& e) {
    fail(path, e.what());
  }
}

MeshFile read_mesh_impl(const std::string& path, bool drop_collapsed);

}  // namespace

MeshFile read_mesh(const std::string& path, bool drop_collapsed) {
  try {
    return read_mesh_impl(path, drop_collapsed);
  } catch (const MeshError&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory while parsing (corrupt counts in the file?)");
  } catch (const std::exception& e) {
    fail(path, std::string("parser error: ") + e.what());
  }
}

namespace {
MeshFile read_mesh_impl(const std::string& path, bool drop_collapsed) {
  const long long size = file_size(path);
  if (size == -1) fail(path, std::string("no such file (") + std::strerror(errno) + ")");
  if (size == -2) fail(path, "not a regular file");
  if (size == 0) fail(path, "the file is empty");
  const std::string ext = extension(path);
  MeshFile out;
  out.format = ext;
  std::vector<Point> pts;
  std::vector<Polygon> polys;

  if (ext == "obj") {
    std::ifstream is(path);
    if (!is) fail(path, "cannot open the file");
    const bool ok = CGAL::IO::read_OBJ(is, pts, polys, CGAL::parameters::verbose(false));
    if (!ok) {
      const std::string why = diagnose_obj(path);
      if (why.empty() && pts.empty()) fail(path, "no vertices found (not an OBJ mesh?)");
      if (why.empty() && polys.empty()) fail(path, "no faces found (an OBJ point cloud is not a mesh)");
      fail(path, why.empty() ? "malformed OBJ file" : why);
    }
    fill_mesh(out, pts, polys);
  } else if (ext == "off") {
    {
      std::ifstream hs(path, std::ios::binary);
      std::string first;
      std::getline(hs, first);
      if (first.find("BINARY") != std::string::npos) {
        read_binary_off(path, hs, size, pts, polys, out);
        fill_mesh(out, pts, polys);
        finish(path, out, drop_collapsed);
        return out;
      }
    }
    long long nv = 0, nf = 0;
    {
      std::ifstream hs(path);
      read_off_counts(path, hs, nv, nf);
    }
    std::ifstream is(path);
    const bool ok = CGAL::IO::read_OFF(is, pts, polys, CGAL::parameters::verbose(false));
    if (!ok)
      fail(path, "could not parse the OFF data: the header declares " + std::to_string(nv) + " vertices and " +
                     std::to_string(nf) + " faces (truncated or malformed file)");
    if (static_cast<long long>(pts.size()) != nv || static_cast<long long>(polys.size()) != nf)
      fail(path, "OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                     " faces, but only " + std::to_string(pts.size()) + " vertices and " +
                     std::to_string(polys.size()) + " faces could be read (truncated or malformed file)");
    fill_mesh(out, pts, polys);
  } else if (ext == "ply") {
    std::ifstream is(path, std::ios::binary);
    if (!is) fail(path, "cannot open the file");
    const PlyHeader h = read_ply_header(path, is);
    out.binary = h.format != "ascii";
    out.float32 = h.float32;
    if (out.binary && h.vertex_fixed) {
      // Each face record holds at least a count byte and 3 indices of >= 1 byte.
      const long long min_size = h.header_bytes + h.n_vertices * h.vertex_record_bytes + h.n_faces * std::max(4LL, h.face_min_bytes);
      if (size < min_size)
        fail(path, "truncated binary PLY: the header declares " + std::to_string(h.n_vertices) + " vertices and " +
                       std::to_string(h.n_faces) + " faces, which need at least " + std::to_string(min_size) +
                       " bytes, but the file has " + std::to_string(size));
    }
    is.clear();
    is.seekg(0);
    CGAL::IO::set_mode(is, out.binary ? CGAL::IO::BINARY : CGAL::IO::ASCII);
    const bool ok = CGAL::IO::read_PLY(is, pts, polys, CGAL::parameters::verbose(false));
    if (!ok)
      fail(path, "could not parse the PLY data: the header declares " + std::to_string(h.n_vertices) + " vertices and " +
                     std::to_string(h.n_faces) + " faces (truncated or malformed file)");
    if (static_cast<long long>(pts.size()) != h.n_vertices || static_cast<long long>(polys.size()) != h.n_faces)
      fail(path, "PLY header declares " + std::to_string(h.n_vertices) + " vertices and " +
                     std::to_string(h.n_faces) + " faces, but " + std::to_string(pts.size()) + " vertices and " +
                     std::to_string(polys.size()) + " faces could be read (truncated or malformed file)");
    fill_mesh(out, pts, polys);
  } else if (ext == "stl") {
    std::ifstream is(path, std::ios::binary);
    if (!is) fail(path, "cannot open the file");
    char head[84] = {0};
    is.read(head, 84);
    const bool looks_ascii = std::strncmp(head, "solid", 5) == 0;
    std::uint32_t n_tri = 0;
    std::memcpy(&n_tri, head + 80, 4);
    const bool exact_binary = size >= 84 && size == 84 + 50LL * n_tri;
    out.binary = !looks_ascii || exact_binary;
    out.float32 = out.binary;  // ASCII STL stores decimal text, read as double
    if (out.binary) {
      if (size < 84) fail(path, "truncated binary STL: " + std::to_string(size) + " bytes, less than the 84-byte header");
      if (size < 84 + 50LL * n_tri)
        fail(path, "truncated binary STL: the header declares " + std::to_string(n_tri) + " triangles (" +
                       std::to_string(84 + 50LL * n_tri) + " bytes) but the file has " + std::to_string(size) + " bytes");
      if (n_tri == 0) fail(path, "binary STL with no triangles");
    }
    is.clear();
    is.seekg(0);
    std::vector<std::array<std::size_t, 3>> tris;
    const bool ok = CGAL::IO::read_STL(is, pts, tris, CGAL::parameters::verbose(false).use_binary_mode(out.binary));
    if (!ok || tris.empty()) fail(path, out.binary ? "malformed binary STL" : "malformed ASCII STL (truncated, or a facet without 3 vertices)");
    polys.reserve(tris.size());
    for (const auto& t : tris) polys.push_back({t[0], t[1], t[2]});
    fill_mesh(out, pts, polys);
  } else {
    fail(path, "unsupported format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
                   "' (supported: .obj .off .ply .stl)");
  }
  finish(path, out, drop_collapsed);
  return out;
}
}  // namespace

void write_mesh(const std::string& path, const Eigen::Ref<const MatrixX3dR>& V, const Polygons& P,
                const WriteOptions& options) {
  validate_mesh(V, P);
  const std::string ext = extension(path);
  if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
    throw MeshError("cannot write '" + path + "': unsupported format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
                    "' (supported: .obj .off .ply .stl)");
  const bool binary = options.binary && (ext == "ply" || ext == "stl");
  std::ofstream os(path, binary ? std::ios::binary : std::ios::out);
  if (!os) throw MeshError("cannot write '" + path + "': " + std::strerror(errno));
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
  os.flush();
  if (!ok || !os) throw MeshError("cannot write '" + path + "': write failed (disk full or no permission?)");
}

}  // namespace meshmark
