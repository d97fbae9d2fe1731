// read_mesh: the reader of the file's format (read_obj.cpp, read_off.cpp, read_ply.cpp and, through
// CGAL, read_stl.cpp), then the faces that repeat a vertex, then validation. OBJ, OFF and PLY are
// read with our own bounded parsers: CGAL's readers trusted the counts in the file: a PLY whose x/y/z were not float or
// double crashed them, and a header or face line declaring 10^9 items made them allocate gigabytes
// before failing. Here every count is checked against the bytes left in the file before anything is
// allocated for it, so no allocation exceeds a small multiple of the file size (the fuzz test,
// tests/test_fuzz_readers.py, holds it to 20x + 64 MB), and every message built from file content
// goes through printable() so it is valid UTF-8.
#include "file_extension.h"
#include "read_common.h"
#include "meshmark/validate.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>
#include <vector>

namespace meshmark {

using detail::Reader;

namespace {

// Faces that repeat a vertex: consecutive repeats are merged ((a,b,b,c) -> (a,b,c)); a face left
// with fewer than 3 corners, or still repeating a vertex, is dropped when drop_collapsed is set
// (STL triangles whose corners weld together are the usual case). Then the mesh is validated.
void finish(const Reader& r, MeshFile& out, bool drop_collapsed) {
  Polygons& P = out.P;
  const Offset m = P.n_faces();
  out.n_file_faces = m;
  bool any_repeat = false;  // fast path: most files have no face that repeats a vertex
  for (Offset f = 0; f < m && !any_repeat; ++f) {
    const Offset b = P.offsets[f], e = P.offsets[f + 1];
    if (e - b > 64) {  // large polygons: sort a copy instead of the quadratic scan
      std::vector<Index> s(P.indices.data() + b, P.indices.data() + e);
      std::sort(s.begin(), s.end());
      any_repeat = std::adjacent_find(s.begin(), s.end()) != s.end();
      continue;
    }
    for (Offset a = b; a < e && !any_repeat; ++a)
      for (Offset d = a + 1; d < e; ++d)
        if (P.indices[a] == P.indices[d]) {
          any_repeat = true;
          break;
        }
  }
  if (drop_collapsed && any_repeat) {
    VectorXi idx(P.indices.size());
    VectorXo off(m + 1);
    off[0] = 0;
    Offset c = 0, kept = 0;
    std::vector<Index> s;
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
      if (ok) {
        s.assign(idx.data() + start, idx.data() + c);
        std::sort(s.begin(), s.end());
        ok = std::adjacent_find(s.begin(), s.end()) == s.end();
      }
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
    r.fail(e.what());
  }
}

std::string read_all(const Reader& r, const std::string& path, long long size) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) r.fail(std::string("cannot open the file (") + std::strerror(errno) + ")");
  std::string data(static_cast<size_t>(size), '\0');
  const size_t got = std::fread(&data[0], 1, data.size(), f);
  std::fclose(f);
  if (got != data.size()) r.fail("the file could not be read completely (" + std::to_string(got) + " of " +
                                 std::to_string(size) + " bytes)");
  return data;
}

MeshFile read_mesh_impl(const Reader& r, const std::string& path, bool drop_collapsed) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) r.fail(std::string("no such file (") + std::strerror(errno) + ")");
  if (!S_ISREG(st.st_mode)) r.fail("not a regular file");
  const long long size = static_cast<long long>(st.st_size);
  if (size == 0) r.fail("the file is empty");
  const std::string ext = detail::file_extension(path);
  MeshFile out;
  out.format = ext;
  if (ext == "obj" || ext == "off" || ext == "ply") {
    const std::string data = read_all(r, path, size);
    if (ext == "obj") detail::read_obj(r, data, out);
    else if (ext == "off") detail::read_off(r, data, out);
    else detail::read_ply(r, data, out);
  } else if (ext == "stl") {
    detail::read_stl(r, path, size, out);
  } else {
    r.fail("unsupported format '" + (ext.empty() ? std::string("(no extension)") : "." + printable(ext, 20)) +
           "' (supported: .obj .off .ply .stl)");
  }
  finish(r, out, drop_collapsed);
  return out;
}

}  // namespace

MeshFile read_mesh(const std::string& path, bool drop_collapsed) {
  const Reader r{printable(path, 400)};
  try {
    return read_mesh_impl(r, path, drop_collapsed);
  } catch (const MeshError&) {
    throw;
  } catch (const std::bad_alloc&) {
    r.fail("out of memory while parsing");
  } catch (const std::exception& e) {
    r.fail(std::string("parser error: ") + printable(e.what(), 200));
  }
}

}  // namespace meshmark
