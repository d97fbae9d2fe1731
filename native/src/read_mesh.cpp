// Reading OBJ, OFF and PLY files with our own bounded parsers (STL goes through CGAL, see
// mesh_io.cpp). CGAL's readers trusted the counts in the file: a PLY whose x/y/z were not float or
// double crashed them, and a header or face line declaring 10^9 items made them allocate gigabytes
// before failing. Here every count is checked against the bytes left in the file before anything is
// allocated for it, so no allocation exceeds a small multiple of the file size (the fuzz test,
// tests/test_fuzz_readers.py, holds it to 20x + 64 MB), and every message built from file content
// goes through printable() so it is valid UTF-8.
#include "meshmark/error.h"
#include "meshmark/printable.h"
#include "meshmark/read_mesh.h"
#include "meshmark/validate.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace meshmark {

namespace detail {
// mesh_io.cpp: binary and ASCII STL through CGAL (counts checked there against the file size).
void read_stl(const std::string& path, const std::string& shown, long long size, MeshFile& out);
}  // namespace detail

namespace {

constexpr long long kMaxCount = std::numeric_limits<Index>::max();  // vertices and faces: int32 indices

struct Reader {
  std::string shown;  // the path as shown in messages (printable)

  [[noreturn]] void fail(const std::string& what) const { throw MeshError("cannot read '" + shown + "': " + what); }
};

std::string extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string quote(const char* b, const char* e) { return "'" + printable(std::string(b, e), 40) + "'"; }

// --- tokens ----------------------------------------------------------------------------------
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Whitespace-separated tokens of one line [p, end).
struct LineTokens {
  const char* p;
  const char* end;
  bool next(const char*& b, const char*& e) {
    while (p < end && is_space(*p)) ++p;
    if (p >= end) return false;
    b = p;
    while (p < end && !is_space(*p)) ++p;
    e = p;
    return true;
  }
};

// Lines of a text buffer; `line` is the 1-based number of the line last returned.
struct Lines {
  const char* p;
  const char* end;
  long long line = 0;
  bool next(const char*& b, const char*& e) {
    if (p >= end) return false;
    b = p;
    const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));
    e = nl ? static_cast<const char*>(nl) : end;
    p = nl ? e + 1 : end;
    ++line;
    return true;
  }
};

bool parse_double(const char* b, const char* e, double& v) {
  if (b < e && *b == '+') ++b;
  if (b >= e) return false;
  const auto r = std::from_chars(b, e, v);
  if (r.ec == std::errc::result_out_of_range) {  // overflow/underflow: strtod gives +-HUGE_VAL or 0
    std::string s(b, e);
    v = std::strtod(s.c_str(), nullptr);
    return true;
  }
  return r.ec == std::errc() && r.ptr == e;
}

// 0 ok, 1 not an integer, 2 out of the 64-bit range
int parse_int(const char* b, const char* e, long long& v) {
  if (b < e && *b == '+') ++b;
  if (b >= e) return 1;
  const auto r = std::from_chars(b, e, v);
  if (r.ec == std::errc::result_out_of_range) return r.ptr == e ? 2 : 1;
  return (r.ec == std::errc() && r.ptr == e) ? 0 : 1;
}

Index to_index(long long v) { return (v < 0 || v > kMaxCount) ? -1 : static_cast<Index>(v); }

// Flat output being built; moved into the MeshFile at the end.
struct Builder {
  std::vector<double> xyz;
  std::vector<Index> idx;
  std::vector<Offset> off{0};

  void to(MeshFile& out) {
    const Eigen::Index n = static_cast<Eigen::Index>(xyz.size() / 3);
    out.V = Eigen::Map<const MatrixX3dR>(xyz.data(), n, 3);
    std::vector<double>().swap(xyz);
    out.P.indices = Eigen::Map<const VectorXi>(idx.data(), static_cast<Eigen::Index>(idx.size()));
    std::vector<Index>().swap(idx);
    out.P.offsets = Eigen::Map<const VectorXo>(off.data(), static_cast<Eigen::Index>(off.size()));
    std::vector<Offset>().swap(off);
  }
};

// --- OBJ -------------------------------------------------------------------------------------
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

// --- OFF -------------------------------------------------------------------------------------
template <class T>
T load(const unsigned char* p, bool big) {
  unsigned char b[sizeof(T)];
  for (size_t i = 0; i < sizeof(T); ++i) b[i] = big ? p[sizeof(T) - 1 - i] : p[i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// Binary OFF ("OFF BINARY"): counts, float32 coordinates and int32 face records. The format is
// big-endian by its definition, but pmp-library and others write it little-endian; this takes the
// endianness for which the counts fit the file size.
void read_binary_off(const Reader& r, const std::string& data, size_t start, MeshFile& out) {
  const unsigned char* buf = reinterpret_cast<const unsigned char*>(data.data()) + start;
  const long long body = static_cast<long long>(data.size() - start);
  if (body < 12) r.fail("truncated binary OFF: no vertex/face counts after the header");
  bool big = true;
  std::int32_t nv = load<std::int32_t>(buf, true), nf = load<std::int32_t>(buf + 4, true);
  auto fits = [&](std::int32_t a, std::int32_t b) { return a >= 0 && b >= 0 && 12 + 12LL * a + 16LL * b <= body; };
  if (!fits(nv, nf)) {
    big = false;
    nv = load<std::int32_t>(buf, false);
    nf = load<std::int32_t>(buf + 4, false);
    if (!fits(nv, nf)) r.fail("truncated or malformed binary OFF: the vertex/face counts do not fit the file size");
  }
  out.binary = true;
  out.float32 = true;
  Builder B;
  B.xyz.resize(3 * static_cast<size_t>(nv));
  long long p = 12;
  for (size_t i = 0; i < 3 * static_cast<size_t>(nv); ++i, p += 4) B.xyz[i] = load<float>(buf + p, big);
  B.off.reserve(static_cast<size_t>(nf) + 1);
  B.idx.reserve(3 * static_cast<size_t>(nf));
  for (std::int32_t f = 0; f < nf; ++f) {
    if (p + 4 > body) r.fail("truncated binary OFF: face " + std::to_string(f) + " is cut off");
    const std::int32_t k = load<std::int32_t>(buf + p, big);
    p += 4;
    if (k < 0 || p + 4LL * k > body)
      r.fail("truncated or malformed binary OFF: face " + std::to_string(f) + " declares " + std::to_string(k) + " corners");
    for (std::int32_t j = 0; j < k; ++j, p += 4) B.idx.push_back(to_index(load<std::int32_t>(buf + p, big)));
    // the number of colour components that may follow; none in the files we know, taken as 0
    if (p + 4 <= body) {
      const std::int32_t nc = load<std::int32_t>(buf + p, big);
      if (nc == 0) p += 4;
    }
    B.off.push_back(static_cast<Offset>(B.idx.size()));
  }
  B.to(out);
}

void read_off(const Reader& r, const std::string& data, MeshFile& out) {
  {
    const size_t nl = data.find('\n');
    const std::string first = data.substr(0, nl == std::string::npos ? data.size() : nl);
    if (first.find("BINARY") != std::string::npos) {
      read_binary_off(r, data, nl == std::string::npos ? data.size() : nl + 1, out);
      return;
    }
  }
  Lines L{data.data(), data.data() + data.size()};
  const char *lb, *le;
  // Header: an optional magic word (OFF, COFF, NOFF, STOFF, ...) then the counts nv nf [ne].
  long long nums[2] = {0, 0};
  int n_nums = 0;
  bool magic = false;
  while (n_nums < 2 && L.next(lb, le)) {
    const char* hash = static_cast<const char*>(std::memchr(lb, '#', static_cast<size_t>(le - lb)));
    LineTokens T{lb, hash ? hash : le};
    const char *b, *e;
    while (n_nums < 2 && T.next(b, e)) {
      const std::string tok(b, e);
      if (!magic && n_nums == 0 && tok.find("OFF") != std::string::npos) {
        magic = true;
        continue;
      }
      long long v;
      if (parse_int(b, e, v) != 0)
        r.fail("OFF header: expected vertex/face/edge counts, found " + quote(b, e));
      nums[n_nums++] = v;
    }
  }
  if (n_nums < 2) r.fail("OFF header has no vertex and face counts (empty or truncated file)");
  const long long nv = nums[0], nf = nums[1];
  if (nv < 0 || nf < 0) r.fail("OFF header has negative counts");
  if (nv > kMaxCount || nf > kMaxCount)
    r.fail("OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
           " faces; at most " + std::to_string(kMaxCount) + " of each are supported");
  // Smallest records: "0 0 0\n" (6 bytes) per vertex and "3 0 1 2\n" (8 bytes) per face.
  const long long left = static_cast<long long>(L.end - L.p);
  const long long need = 6 * nv + 8 * nf;
  const std::string declared = "the header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces";
  if (need > left + 1)
    r.fail("could not parse the OFF data: " + declared + " (truncated or malformed file): they need at least " +
           std::to_string(need) + " bytes but " + std::to_string(left) + " follow the header");
  Builder B;
  B.xyz.reserve(3 * static_cast<size_t>(nv));
  B.off.reserve(static_cast<size_t>(nf) + 1);
  B.idx.reserve(3 * static_cast<size_t>(nf));
  long long done_v = 0, done_f = 0;
  while ((done_v < nv || done_f < nf) && L.next(lb, le)) {
    const char* hash = static_cast<const char*>(std::memchr(lb, '#', static_cast<size_t>(le - lb)));
    LineTokens T{lb, hash ? hash : le};
    const char *b, *e;
    if (!T.next(b, e)) continue;  // blank or comment line
    const std::string ln = "line " + std::to_string(L.line) + ": ";
    if (done_v < nv) {
      for (int k = 0; k < 3; ++k) {
        if (k > 0 && !T.next(b, e)) r.fail(ln + "vertex " + std::to_string(done_v) + " has fewer than 3 coordinates");
        double x;
        if (!parse_double(b, e, x)) r.fail(ln + quote(b, e) + " is not a number");
        B.xyz.push_back(x);
      }
      ++done_v;
      continue;
    }
    long long k;
    if (parse_int(b, e, k) != 0 || k < 0)
      r.fail(ln + "face " + std::to_string(done_f) + ": the corner count " + quote(b, e) + " is not a non-negative integer");
    for (long long j = 0; j < k; ++j) {
      if (!T.next(b, e))
        r.fail(ln + "face " + std::to_string(done_f) + " declares " + std::to_string(k) + " corners but the line holds " +
               std::to_string(j) + " indices");
      long long v;
      if (parse_int(b, e, v) == 1) r.fail(ln + "face index " + quote(b, e) + " is not an integer");
      B.idx.push_back(to_index(v));
    }
    B.off.push_back(static_cast<Offset>(B.idx.size()));
    ++done_f;
  }
  if (done_v < nv || done_f < nf)
    r.fail("could not parse the OFF data: " + declared + " (truncated or malformed file), but only " +
           std::to_string(done_v) + " vertices and " + std::to_string(done_f) + " faces could be read");
  B.to(out);
}

// --- PLY -------------------------------------------------------------------------------------
enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64, none };

PlyType ply_type(const std::string& t) {
  if (t == "char" || t == "int8") return PlyType::i8;
  if (t == "uchar" || t == "uint8") return PlyType::u8;
  if (t == "short" || t == "int16") return PlyType::i16;
  if (t == "ushort" || t == "uint16") return PlyType::u16;
  if (t == "int" || t == "int32") return PlyType::i32;
  if (t == "uint" || t == "uint32") return PlyType::u32;
  if (t == "float" || t == "float32") return PlyType::f32;
  if (t == "double" || t == "float64") return PlyType::f64;
  return PlyType::none;
}

int ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
    default: return 0;
  }
}

bool ply_integer(PlyType t) { return t != PlyType::f32 && t != PlyType::f64 && t != PlyType::none; }

struct PlyProp {
  std::string name;
  bool list = false;
  PlyType type = PlyType::none;   // value type (the item type of a list)
  PlyType count = PlyType::none;  // list count type
};

struct PlyElement {
  std::string name;
  long long count = 0;
  long long line = 0;
  std::vector<PlyProp> props;
  int x = -1, y = -1, z = -1, vi = -1;  // vertex coordinates, face index list
};

// Reads one value of type t: binary (from data at p, advancing p) or ASCII (the next token).
struct PlyBody {
  const Reader& r;
  const std::string& data;
  size_t p;
  bool ascii, big;
  long long line;  // ASCII: current line number

  bool next_token(const char*& b, const char*& e) {
    const char* s = data.data() + p;
    const char* end = data.data() + data.size();
    while (s < end && (is_space(*s) || *s == '\n')) {
      if (*s == '\n') ++line;
      ++s;
    }
    if (s >= end) {
      p = data.size();
      return false;
    }
    b = s;
    while (s < end && !is_space(*s) && *s != '\n') ++s;
    e = s;
    p = static_cast<size_t>(s - data.data());
    return true;
  }

  size_t left() const { return data.size() - p; }

  // Value as double; integer types are exact below 2^53 (all of them here).
  double value(PlyType t, const PlyElement& el, long long rec, const PlyProp& pr, bool want_integer) {
    if (ascii) {
      const char *b, *e;
      if (!next_token(b, e))
        r.fail("PLY data ends at line " + std::to_string(line) + " inside " + el.name + " " + std::to_string(rec) +
               " (the header declares more records than the file holds; truncated or malformed file)");
      if (ply_integer(t) || want_integer) {
        long long v;
        if (parse_int(b, e, v) != 0)
          r.fail("PLY line " + std::to_string(line) + ": " + el.name + " " + std::to_string(rec) + " property '" +
                 printable(pr.name, 40) + "': " + quote(b, e) + " is not an integer");
        return static_cast<double>(v);
      }
      double v;
      if (!parse_double(b, e, v))
        r.fail("PLY line " + std::to_string(line) + ": " + el.name + " " + std::to_string(rec) + " property '" +
               printable(pr.name, 40) + "': " + quote(b, e) + " is not a number");
      return t == PlyType::f32 ? static_cast<double>(static_cast<float>(v)) : v;  // a float property holds a float
    }
    const size_t n = static_cast<size_t>(ply_size(t));
    if (left() < n)
      r.fail("truncated binary PLY: the data ends inside " + el.name + " " + std::to_string(rec));
    const unsigned char* q = reinterpret_cast<const unsigned char*>(data.data()) + p;
    p += n;
    switch (t) {
      case PlyType::i8: return static_cast<std::int8_t>(q[0]);
      case PlyType::u8: return q[0];
      case PlyType::i16: return load<std::int16_t>(q, big);
      case PlyType::u16: return load<std::uint16_t>(q, big);
      case PlyType::i32: return load<std::int32_t>(q, big);
      case PlyType::u32: return load<std::uint32_t>(q, big);
      case PlyType::f32: return load<float>(q, big);
      case PlyType::f64: return load<double>(q, big);
      default: return 0;
    }
  }
};

void read_ply(const Reader& r, const std::string& data, MeshFile& out) {
  Lines L{data.data(), data.data() + data.size()};
  const char *lb, *le;
  auto line_str = [&](const char* b, const char* e) {
    if (e > b && e[-1] == '\r') --e;
    return std::string(b, e);
  };
  if (!L.next(lb, le) || line_str(lb, le) != "ply") r.fail("not a PLY file (the first line is not 'ply')");
  std::string format;
  std::vector<PlyElement> els;
  bool ended = false;
  while (L.next(lb, le)) {
    const std::string hl = "PLY header line " + std::to_string(L.line) + ": ";
    LineTokens T{lb, le};
    const char *b, *e;
    if (!T.next(b, e)) continue;
    const std::string kw(b, e);
    std::vector<std::string> args;
    while (T.next(b, e) && args.size() < 8) args.emplace_back(b, e);
    if (kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") {
      ended = true;
      break;
    }
    if (kw == "format") {
      if (args.empty()) r.fail(hl + "'format' without a format name");
      format = args[0];
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        r.fail("unknown PLY format '" + printable(format, 40) + "' (expected ascii, binary_little_endian or binary_big_endian)");
    } else if (kw == "element") {
      if (args.size() < 2) r.fail(hl + "'element' needs a name and a count");
      long long count = -1;
      if (parse_int(args[1].data(), args[1].data() + args[1].size(), count) != 0 || count < 0)
        r.fail(hl + "bad element count '" + printable(args[1], 40) + "' (a non-negative integer is needed)");
      if (count > kMaxCount)
        r.fail(hl + "element '" + printable(args[0], 40) + "' declares " + std::to_string(count) + " records; at most " +
               std::to_string(kMaxCount) + " are supported");
      for (const auto& o : els)
        if (o.name == args[0]) r.fail(hl + "element '" + printable(args[0], 40) + "' is declared twice");
      PlyElement el;
      el.name = args[0];
      el.count = count;
      el.line = L.line;
      els.push_back(el);
    } else if (kw == "property") {
      if (els.empty()) r.fail(hl + "'property' before any 'element'");
      PlyElement& el = els.back();
      PlyProp pr;
      if (!args.empty() && args[0] == "list") {
        if (args.size() < 4) r.fail(hl + "'property list' needs a count type, an item type and a name");
        pr.list = true;
        pr.count = ply_type(args[1]);
        pr.type = ply_type(args[2]);
        pr.name = args[3];
        if (pr.count == PlyType::none || pr.type == PlyType::none)
          r.fail(hl + "unknown PLY type in '" + printable(line_str(lb, le), 80) + "'");
        if (!ply_integer(pr.count)) r.fail(hl + "a list count must have an integer type, not '" + printable(args[1], 20) + "'");
      } else {
        if (args.size() < 2) r.fail(hl + "'property' needs a type and a name");
        pr.type = ply_type(args[0]);
        pr.name = args[1];
        if (pr.type == PlyType::none) r.fail(hl + "unknown PLY type '" + printable(args[0], 20) + "'");
      }
      for (const auto& o : el.props)
        if (o.name == pr.name) r.fail(hl + "property '" + printable(pr.name, 40) + "' is declared twice");
      const int at = static_cast<int>(el.props.size());
      if (el.name == "vertex" && (pr.name == "x" || pr.name == "y" || pr.name == "z")) {
        if (pr.list) r.fail(hl + "vertex coordinate '" + pr.name + "' is declared as a list; a coordinate must be a scalar");
        (pr.name == "x" ? el.x : pr.name == "y" ? el.y : el.z) = at;
      }
      if (el.name == "face" && (pr.name == "vertex_indices" || pr.name == "vertex_index")) {
        if (!pr.list) r.fail(hl + "face property '" + pr.name + "' must be a list of vertex indices");
        if (!ply_integer(pr.type)) r.fail(hl + "face vertex indices must have an integer type, not '" + printable(args[2], 20) + "'");
        if (el.vi >= 0) r.fail(hl + "face has two vertex index lists");
        el.vi = at;
      }
      el.props.push_back(pr);
    } else {
      r.fail(hl + "unknown PLY header keyword '" + printable(kw, 40) + "'");
    }
  }
  if (!ended) r.fail("PLY header has no 'end_header' line (truncated or not a PLY file)");
  if (format.empty()) r.fail("PLY header has no 'format' line");
  const PlyElement* ve = nullptr;
  const PlyElement* fe = nullptr;
  for (const auto& el : els) {
    if (el.name == "vertex") ve = &el;
    if (el.name == "face") fe = &el;
  }
  for (const auto& el : els)
    if (el.count > 0 && el.props.empty())
      r.fail("PLY header line " + std::to_string(el.line) + ": element '" + printable(el.name, 40) + "' has " +
             std::to_string(el.count) + " records but no properties");
  if (!ve) r.fail("PLY header declares no 'vertex' element");
  if (!fe) r.fail("PLY header declares no 'face' element");
  for (const char* c : {"x", "y", "z"})
    if ((c[0] == 'x' ? ve->x : c[0] == 'y' ? ve->y : ve->z) < 0)
      r.fail("PLY header line " + std::to_string(ve->line) + ": element 'vertex' has no '" + c + "' property");
  if (fe->vi < 0)
    r.fail("PLY header line " + std::to_string(fe->line) + ": element 'face' has no 'vertex_indices' list");
  const bool ascii = format == "ascii";
  out.binary = !ascii;
  out.float32 = ve->props[ve->x].type == PlyType::f32 && ve->props[ve->y].type == PlyType::f32 &&
                ve->props[ve->z].type == PlyType::f32;

  // Every record needs at least this many bytes: binary, the scalar sizes and the list counts;
  // ASCII, one character and a separator per value.
  const size_t header_end = static_cast<size_t>(L.p - data.data());
  const long long body = static_cast<long long>(data.size() - header_end);
  long long need = 0;
  for (const auto& el : els) {
    long long rec = 0;
    for (int k = 0; k < static_cast<int>(el.props.size()); ++k) {
      const PlyProp& pr = el.props[k];
      rec += ascii ? 2 : ply_size(pr.list ? pr.count : pr.type);
      if (&el == fe && k == fe->vi) rec += 3 * (ascii ? 2 : ply_size(pr.type));  // a face has >= 3 corners
    }
    if (el.count > 0 && rec == 0)
      r.fail("PLY header line " + std::to_string(el.line) + ": element '" + printable(el.name, 40) + "' has " +
             std::to_string(el.count) + " records but no properties");
    if (el.count > 0 && (body + 1) / rec < el.count) {
      need = -1;
      break;
    }
    need += el.count * rec;
    if (need > body + 1) break;
  }
  if (need < 0 || need > body + 1)
    r.fail(std::string(ascii ? "truncated or malformed ASCII PLY" : "truncated binary PLY") + ": the header declares " +
           std::to_string(ve->count) + " vertices and " + std::to_string(fe->count) + " faces, which need " +
           (need < 0 ? std::string("far more") : "at least " + std::to_string(need)) + " bytes, but " + std::to_string(body) +
           " follow the header (truncated or malformed file)");

  PlyBody in{r, data, header_end, ascii, format == "binary_big_endian", L.line + 1};
  Builder B;
  B.xyz.resize(3 * static_cast<size_t>(ve->count));
  B.off.reserve(static_cast<size_t>(fe->count) + 1);
  B.idx.reserve(std::min<size_t>(3 * static_cast<size_t>(fe->count), static_cast<size_t>(body)));
  for (const auto& el : els) {
    const bool is_v = &el == ve, is_f = &el == fe;
    std::string what = is_v ? "vertex" : is_f ? "face" : "record of element '" + printable(el.name, 40) + "'";
    PlyElement named = el;
    named.name = what;
    for (long long i = 0; i < el.count; ++i) {
      for (int k = 0; k < static_cast<int>(el.props.size()); ++k) {
        const PlyProp& pr = el.props[k];
        if (!pr.list) {
          const double v = in.value(pr.type, named, i, pr, false);
          if (is_v) {
            if (k == el.x) B.xyz[3 * i] = v;
            else if (k == el.y) B.xyz[3 * i + 1] = v;
            else if (k == el.z) B.xyz[3 * i + 2] = v;
          }
          continue;
        }
        const double cd = in.value(pr.count, named, i, pr, true);
        if (!ascii && cd * ply_size(pr.type) > static_cast<double>(in.left()))
          r.fail("truncated binary PLY: " + what + " " + std::to_string(i) + " declares a list of " +
                 std::to_string(static_cast<long long>(cd)) + " items but only " + std::to_string(in.left()) + " bytes are left");
        if (cd < 0 || cd > static_cast<double>(in.left()))  // every item takes at least one byte
          r.fail(std::string(ascii ? "PLY line " + std::to_string(in.line) + ": " : "PLY data: ") + what + " " +
                 std::to_string(i) + " declares a list of " + std::to_string(static_cast<long long>(cd)) +
                 " items but only " + std::to_string(in.left()) + " bytes are left in the file (truncated or malformed file)");
        const long long count = static_cast<long long>(cd);
        const bool indices = is_f && k == el.vi;
        for (long long j = 0; j < count; ++j) {
          const double v = in.value(pr.type, named, i, pr, indices);
          if (indices) B.idx.push_back(to_index(static_cast<long long>(v)));
        }
      }
      if (is_f) B.off.push_back(static_cast<Offset>(B.idx.size()));
    }
  }
  B.to(out);
}

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
  const std::string ext = extension(path);
  MeshFile out;
  out.format = ext;
  if (ext == "obj" || ext == "off" || ext == "ply") {
    const std::string data = read_all(r, path, size);
    if (ext == "obj") read_obj(r, data, out);
    else if (ext == "off") read_off(r, data, out);
    else read_ply(r, data, out);
  } else if (ext == "stl") {
    detail::read_stl(path, r.shown, size, out);
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
