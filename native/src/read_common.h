// meshmark: what the mesh readers share (private to native/src): the failure message, tokens and
// lines of a text buffer, number parsing, endian loads and the flat output being built. Every format
// has one reader in its own file (read_obj.cpp, read_off.cpp, read_ply.cpp, read_stl.cpp); read_mesh
// (read_mesh.cpp) picks one by the extension and checks the result.
#pragma once
#include "meshmark/error.h"
#include "meshmark/printable.h"
#include "meshmark/read_mesh.h"

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

namespace meshmark::detail {

constexpr long long kMaxCount = std::numeric_limits<Index>::max();  // vertices and faces: int32 indices

struct Reader {
  std::string shown;  // the path as shown in messages (printable)

  [[noreturn]] void fail(const std::string& what) const { throw MeshError("cannot read '" + shown + "': " + what); }
};

inline std::string quote(const char* b, const char* e) { return "'" + printable(std::string(b, e), 40) + "'"; }

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

inline bool parse_double(const char* b, const char* e, double& v) {
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
inline int parse_int(const char* b, const char* e, long long& v) {
  if (b < e && *b == '+') ++b;
  if (b >= e) return 1;
  const auto r = std::from_chars(b, e, v);
  if (r.ec == std::errc::result_out_of_range) return r.ptr == e ? 2 : 1;
  return (r.ec == std::errc() && r.ptr == e) ? 0 : 1;
}

inline Index to_index(long long v) { return (v < 0 || v > kMaxCount) ? -1 : static_cast<Index>(v); }

// A value of type T stored little- or big-endian at p.
template <class T>
T load(const unsigned char* p, bool big) {
  unsigned char b[sizeof(T)];
  for (size_t i = 0; i < sizeof(T); ++i) b[i] = big ? p[sizeof(T) - 1 - i] : p[i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

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

// The readers: each fills out.V, out.P (and out.binary/out.float32) from the whole file or throws
// r.fail(...) naming what is wrong. Counts are checked against the bytes left before any allocation.
void read_obj(const Reader& r, const std::string& data, MeshFile& out);
void read_off(const Reader& r, const std::string& data, MeshFile& out);
void read_ply(const Reader& r, const std::string& data, MeshFile& out);
void read_stl(const Reader& r, const std::string& path, long long size, MeshFile& out);  // through CGAL

}  // namespace meshmark::detail
