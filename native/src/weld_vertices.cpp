#include "meshmark/weld_vertices.h"
#include "meshmark/error.h"

#include <cstdint>
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

namespace meshmark {

namespace {
inline std::uint64_t bits_of(double x) {
  x += 0.0;  // -0.0 + 0.0 == +0.0: equal doubles get equal bits (V is finite)
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}

inline std::uint64_t hash_of(const double* p) {
  std::uint64_t h = bits_of(p[0]) * 0x9e3779b97f4a7c15ULL ^ bits_of(p[1]) * 0xc2b2ae3d27d4eb4fULL ^
                    bits_of(p[2]) * 0x165667b19e3779f9ULL;
  h ^= h >> 29;  // fold the high bits (where the multiplications put the mixing) down
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 32;
  return h;
}
}  // namespace

Welded weld_vertices(const Eigen::Ref<const MatrixX3dR>& V, const PolygonsView& P) {
  const Eigen::Index n = V.rows();
  Welded W;
  W.map.resize(n);
  std::vector<Index> first;
  first.reserve(static_cast<size_t>(n));

  // Pass 1: hash every position into an open-addressing table (linear probing, load <= 2/3).
  // A slot holds (tag << 32 | welded index + 1), 0 = empty: the 32-bit tag (high hash bits) avoids
  // reading the coordinates of a different position that shares the slot. The table is far larger
  // than the caches, so the slot of vertex i + AHEAD is prefetched while vertex i is looked up.
  std::uint64_t size = 16;
  while (2 * size < 3 * static_cast<std::uint64_t>(n)) size <<= 1;
  const std::uint64_t mask = size - 1;
  std::vector<std::uint64_t> table(size, 0);
  const double* v = V.data();
  constexpr Eigen::Index AHEAD = 16;  // a power of two: ring[] holds the hashes of i .. i + AHEAD - 1
  std::uint64_t ring[AHEAD];
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(AHEAD, n); ++i) {
    ring[i] = hash_of(v + 3 * i);
    __builtin_prefetch(&table[ring[i] & mask]);
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* p = v + 3 * i;
    const std::uint64_t h = ring[i & (AHEAD - 1)];
    if (i + AHEAD < n) {
      const std::uint64_t ha = hash_of(v + 3 * (i + AHEAD));
      ring[i & (AHEAD - 1)] = ha;
      __builtin_prefetch(&table[ha & mask]);
    }
    const std::uint64_t tag = h >> 32;
    std::uint64_t s = h & mask;
    for (;;) {
      const std::uint64_t e = table[s];
      if (e == 0) {
        const Index j = static_cast<Index>(first.size());
        table[s] = tag << 32 | static_cast<std::uint64_t>(j + 1);
        W.map[i] = j;
        first.push_back(static_cast<Index>(i));
        break;
      }
      if ((e >> 32) == tag) {
        const Index j = static_cast<Index>((e & 0xffffffffULL) - 1);
        const double* q = v + 3 * static_cast<Eigen::Index>(first[j]);
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
          W.map[i] = j;
          break;
        }
      }
      s = (s + 1) & mask;
    }
  }
  W.first = Eigen::Map<const VectorXi>(first.data(), static_cast<Eigen::Index>(first.size()));
  if (static_cast<Eigen::Index>(first.size()) == n) {  // nothing merges: the faces stay as they are
    W.indices.resize(0);
    W.offsets.resize(0);
    W.face.resize(0);
    return W;
  }

  // Pass 2: reindex the faces, drop repeated consecutive corners and faces that collapse.
  const Offset m = P.n_faces;
  W.indices.resize(P.n_corners);
  W.offsets.resize(m + 1);
  W.face.resize(m);
  Offset c_out = 0, f_out = 0;
  W.offsets[0] = 0;
  for (Offset f = 0; f < m; ++f) {
    const Offset b = P.offsets[f], e = P.offsets[f + 1];
    const Offset start = c_out;
    for (Offset c = b; c < e; ++c) {
      const Index u = P.indices[c];
      if (u < 0 || u >= n)
        throw MeshError("face " + std::to_string(f) + " refers to vertex " + std::to_string(u) + ", but the mesh has " +
                        std::to_string(n) + " vertices");
      const Index w = W.map[u];
      if (c_out > start && W.indices[c_out - 1] == w) continue;
      W.indices[c_out++] = w;
    }
    while (c_out - start > 1 && W.indices[c_out - 1] == W.indices[start]) --c_out;  // cyclic repeat
    bool keep = c_out - start >= 3;
    for (Offset a = start; keep && a < c_out; ++a)  // faces are small: a quadratic scan
      for (Offset d = a + 1; d < c_out; ++d)
        if (W.indices[a] == W.indices[d]) {
          keep = false;
          break;
        }
    if (!keep) {
      c_out = start;
      continue;
    }
    W.face[f_out++] = static_cast<Index>(f);
    W.offsets[f_out] = c_out;
  }
  W.indices.conservativeResize(c_out);
  W.offsets.conservativeResize(f_out + 1);
  W.face.conservativeResize(f_out);
  return W;
}

}  // namespace meshmark
