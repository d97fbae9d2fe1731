// Reading PLY: ASCII and binary (both byte orders), any element and property layout; x, y, z of
// "vertex" and the index list of "face" are kept, every record is bounds-checked.
#include "read_common.h"

#include <algorithm>
#include <cstdint>

namespace meshmark::detail {

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

}  // namespace meshmark::detail
