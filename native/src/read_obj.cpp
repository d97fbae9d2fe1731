// Reading Wavefront OBJ: v and f/fo records (polygons kept, negative indices relative); texture,
// normal, group and material statements are skipped, line and point elements refused.
#include "read_common.h"

#include <cmath>

namespace meshmark::detail {

void read_obj(const Reader& r, const std::string& data, MeshFile& out) {
  static const char* ignored[] = {"vt", "vn", "vp", "o", "g", "s", "usemtl", "mtllib", "mg", "bevel", "lod",
                                  "cstype", "deg", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp",
                                  "end", "con", "step", "bmat", "c_interp", "d_interp", "shadow_obj", "trace_obj",
                                  "ctech", "stech", "maplib", "usemap"};
  Builder B;
  std::vector<long long> face_line;  // line of each face, for the out-of-range message
  Lines L{data.data(), data.data() + data.size()};
  const char *lb, *le;
  while (L.next(lb, le)) {
    const char* hash = static_cast<const char*>(std::memchr(lb, '#', static_cast<size_t>(le - lb)));
    LineTokens T{lb, hash ? hash : le};
    const char *kb, *ke;
    if (!T.next(kb, ke)) continue;
    const std::string ln = "line " + std::to_string(L.line) + ": ";
    const size_t klen = static_cast<size_t>(ke - kb);
    auto kw_is = [&](const char* k) { return std::strlen(k) == klen && std::memcmp(kb, k, klen) == 0; };
    if (kw_is("v")) {
      for (int k = 0; k < 3; ++k) {
        const char *b, *e;
        if (!T.next(b, e)) r.fail(ln + "vertex has fewer than 3 coordinates");
        double x;
        if (!parse_double(b, e, x)) r.fail(ln + quote(b, e) + " is not a number");
        if (!std::isfinite(x)) r.fail(ln + "vertex coordinate " + quote(b, e) + " is not finite");
        B.xyz.push_back(x);
      }
    } else if (kw_is("f") || kw_is("fo")) {
      const long long nv = static_cast<long long>(B.xyz.size() / 3);
      const char *b, *e;
      int corners = 0;
      while (T.next(b, e)) {
        const char* slash = static_cast<const char*>(std::memchr(b, '/', static_cast<size_t>(e - b)));
        const char* ie = slash ? slash : e;
        long long v = 0;
        const int st = parse_int(b, ie, v);
        if (st == 1) r.fail(ln + "face index " + quote(b, e) + " is not an integer");
        if (st == 2 || v > kMaxCount || v < -kMaxCount) r.fail(ln + "face index " + quote(b, e) + " is out of range");
        if (v == 0) r.fail(ln + "face index 0 (OBJ indices start at 1)");
        if (v < 0) {
          if (nv + v < 0)
            r.fail(ln + "face index " + std::to_string(v) + " refers to a vertex that does not exist (" +
                   std::to_string(nv) + " vertices before this line)");
          B.idx.push_back(static_cast<Index>(nv + v));
        } else {
          B.idx.push_back(static_cast<Index>(v - 1));
        }
        ++corners;
      }
      if (corners < 3)
        r.fail(ln + "a face needs at least 3 vertices, this one has " + std::to_string(corners));
      B.off.push_back(static_cast<Offset>(B.idx.size()));
      face_line.push_back(L.line);
    } else if (kw_is("l") || kw_is("p")) {
      r.fail(ln + "OBJ " + quote(kb, ke) + " (line/point) elements are not supported");
    } else {
      bool ok = false;
      for (const char* k : ignored) ok = ok || kw_is(k);
      if (!ok) r.fail(ln + "unrecognized OBJ statement " + quote(kb, ke));
    }
  }
  const long long nv = static_cast<long long>(B.xyz.size() / 3);
  if (nv == 0) r.fail("no vertices found (not an OBJ mesh?)");
  if (face_line.empty()) r.fail("no faces found (an OBJ point cloud is not a mesh)");
  for (size_t f = 0; f < face_line.size(); ++f)
    for (Offset c = B.off[f]; c < B.off[f + 1]; ++c)
      if (B.idx[static_cast<size_t>(c)] >= nv)
        r.fail("line " + std::to_string(face_line[f]) + ": face index " + std::to_string(B.idx[static_cast<size_t>(c)] + 1LL) +
               " refers to a vertex that does not exist (" + std::to_string(nv) + " vertices in the file)");
  B.to(out);
}

}  // namespace meshmark::detail
