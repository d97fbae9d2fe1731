// Reading OFF: ASCII (any magic word ending in OFF, comments, the counts checked against the file
// size) and binary OFF in either byte order.
#include "read_common.h"

#include <cstdint>

namespace meshmark::detail {

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

}  // namespace meshmark::detail
