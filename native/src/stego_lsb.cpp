// §4.3.2 bit layout: quantization, message bits and the LSB stream (see stego_lsb.h).
#include "meshmark/stego_lsb.h"
#include "meshmark/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace meshmark {

namespace {

// One coordinate word: its low bits, the weight exponent of bit 0, whether it can carry.
struct Word {
  std::uint64_t bits = 0;
  int u = 0;
  bool has = false;
};

struct Codec {
  StegoPrecision p;
  int s;  // Fixed32 unit exponent
  int W;  // modifiable width
  Eigen::Vector3d o;

  Codec(StegoPrecision prec, const StegoFrame& fr) : p(prec), s(fr.E - 32), o(fr.o) {
    W = p == StegoPrecision::Fixed32 ? 31 : p == StegoPrecision::Float32 ? 23 : 52;
  }
  Word get(double x, int a) const {
    Word w;
    switch (p) {
      case StegoPrecision::Fixed32: {
        w.bits = static_cast<std::uint64_t>(std::ldexp(x - o[a], -s));
        w.u = s;
        w.has = true;
        break;
      }
      case StegoPrecision::Float32: {
        const float f = static_cast<float>(x);
        std::uint32_t b;
        std::memcpy(&b, &f, 4);
        const int ef = static_cast<int>((b >> 23) & 0xffu);
        w.bits = b;
        w.u = ef - 150;
        w.has = ef != 0;
        break;
      }
      case StegoPrecision::Float64: {
        std::uint64_t b;
        std::memcpy(&b, &x, 8);
        const int ef = static_cast<int>((b >> 52) & 0x7ffu);
        w.bits = b;
        w.u = ef - 1075;
        w.has = ef != 0;
        break;
      }
    }
    return w;
  }
  double put(const Word& w, int a) const {
    switch (p) {
      case StegoPrecision::Fixed32:
        return o[a] + std::ldexp(static_cast<double>(w.bits), s);
      case StegoPrecision::Float32: {
        const std::uint32_t b = static_cast<std::uint32_t>(w.bits);
        float f;
        std::memcpy(&f, &b, 4);
        return static_cast<double>(f);
      }
      case StegoPrecision::Float64:
      default: {
        double x;
        std::memcpy(&x, &w.bits, 8);
        return x;
      }
    }
  }
  // Message bits of a word with k = t - u low bits: positions 1 .. free.
  int free_bits(const Word& w, int t) const {
    if (!w.has) return 0;
    const long k = static_cast<long>(t) - w.u;
    return static_cast<int>(std::max(0L, std::min<long>(k, W) - 1));
  }
  int zero_bits(const Word& w, int t) const {
    if (!w.has) return 0;
    const long k = static_cast<long>(t) - w.u;
    return static_cast<int>(std::max(1L, std::min<long>(k, W)));
  }
};

inline int get_bit(const std::vector<std::uint8_t>& b, std::int64_t i) {
  return (b[static_cast<std::size_t>(i >> 3)] >> (7 - (i & 7))) & 1;
}
inline void set_bit(std::vector<std::uint8_t>& b, std::int64_t i, int v) {
  if (v) b[static_cast<std::size_t>(i >> 3)] |= static_cast<std::uint8_t>(0x80u >> (i & 7));
}

void check_order(Eigen::Index n, const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first) {
  if (order.size() != n || first.size() != n) throw MeshError("order and first must have one entry per vertex");
  for (Eigen::Index i = 0; i < n; ++i)
    if (order[i] < 0 || order[i] >= n) throw MeshError("order[" + std::to_string(i) + "] out of range");
  if (n > 0 && !first[0]) throw MeshError("first[0] must be 1");
}
void check_t(Eigen::Index n, const Eigen::Ref<const VectorXi>& t) {
  if (t.size() != n) throw MeshError("t must have one cell exponent per vertex");
}

}  // namespace

StegoFrame stego_frame(const Eigen::Ref<const MatrixX3dR>& V, StegoPrecision p) {
  if (V.rows() == 0) throw MeshError("empty mesh: no vertices to carry a message");
  StegoFrame fr;
  Eigen::Vector3d lo, hi;
  int E = std::numeric_limits<int>::min();
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int a = 0; a < 3; ++a) {
      double x = V(i, a);
      if (!std::isfinite(x)) throw MeshError("vertex " + std::to_string(i) + " is not finite");
      if (p == StegoPrecision::Float32) {
        if (std::abs(x) > std::numeric_limits<float>::max())
          throw MeshError("vertex " + std::to_string(i) + " does not fit float32");
        x = static_cast<double>(static_cast<float>(x));
      }
      if (i == 0 || x < lo[a]) lo[a] = x;
      if (i == 0 || x > hi[a]) hi[a] = x;
      if (x == 0) continue;
      int e;
      std::frexp(x, &e);
      E = std::max(E, e);
    }
  if (E == std::numeric_limits<int>::min()) throw MeshError("every vertex coordinate is zero: nothing to carry a message");
  if (p != StegoPrecision::Fixed32) {
    fr.E = E;
    return fr;
  }
  // Smallest E with an aligned cube per axis (monotone in E, so the first one found is the smallest).
  const double L = (hi - lo).maxCoeff();
  if (!(L > 0)) throw MeshError("degenerate mesh: all vertices coincide");
  int e;
  std::frexp(L, &e);  // L <= 2^e
  for (int c = e - 1;; ++c) {
    bool ok = true;
    Eigen::Vector3d o;
    for (int a = 0; a < 3 && ok; ++a) {
      o[a] = std::ldexp(std::floor(std::ldexp(lo[a], -(c - 1))), c - 1);
      ok = hi[a] < o[a] + std::ldexp(1.0, c);
    }
    if (ok) {
      for (int a = 0; a < 3; ++a)
        if (std::abs(o[a]) >= std::ldexp(1.0, c + 20))
          throw MeshError("fixed32: the mesh lies more than 2^20 of its sizes from the origin; use float32 or float64");
      fr.E = c;
      fr.o = o;
      return fr;
    }
  }
}

double stego_extent(const Eigen::Ref<const MatrixX3dR>& V) {
  if (V.rows() == 0) return 0;
  Eigen::Vector3d lo = V.row(0).transpose(), hi = lo;
  for (Eigen::Index i = 1; i < V.rows(); ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], V(i, a));
      hi[a] = std::max(hi[a], V(i, a));
    }
  return (hi - lo).maxCoeff();
}

MatrixX3dR stego_snap(const Eigen::Ref<const MatrixX3dR>& V, StegoPrecision p, const StegoFrame& fr) {
  MatrixX3dR out(V.rows(), 3);
  const int s = fr.E - 32;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int a = 0; a < 3; ++a) {
      const double x = V(i, a);
      switch (p) {
        case StegoPrecision::Fixed32: {
          double n = std::floor(std::ldexp(x - fr.o[a], -s));
          n = std::min(std::max(n, 0.0), 4294967295.0);
          out(i, a) = fr.o[a] + std::ldexp(n, s);
          break;
        }
        case StegoPrecision::Float32:
          out(i, a) = static_cast<double>(static_cast<float>(x));
          break;
        case StegoPrecision::Float64:
          out(i, a) = x;
          break;
      }
    }
  return out;
}

std::pair<int, int> stego_t_range(StegoPrecision p, int E) {
  if (p == StegoPrecision::Fixed32) return {E - 31, E - 2};
  return {E - 110, E};
}

MatrixX3dR stego_quantize(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                          StegoPrecision p, const StegoFrame& fr) {
  check_t(C.rows(), t);
  const Codec cd(p, fr);
  MatrixX3dR out(C.rows(), 3);
  for (Eigen::Index i = 0; i < C.rows(); ++i)
    for (int a = 0; a < 3; ++a) {
      Word w = cd.get(C(i, a), a);
      const int z = cd.zero_bits(w, t[i]);
      if (z > 0) w.bits &= ~((std::uint64_t{1} << z) - 1);
      out(i, a) = w.has ? cd.put(w, a) : C(i, a);
    }
  return out;
}

MatrixX3dR stego_clear_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr) {
  const Codec cd(p, fr);
  MatrixX3dR out(C.rows(), 3);
  for (Eigen::Index i = 0; i < C.rows(); ++i)
    for (int a = 0; a < 3; ++a) {
      Word w = cd.get(C(i, a), a);
      if (w.has) {
        w.bits &= ~std::uint64_t{1};
        out(i, a) = cd.put(w, a);
      } else {
        out(i, a) = C(i, a);
      }
    }
  return out;
}

std::int64_t stego_capacity(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                            StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                            const Eigen::Ref<const VectorXb>& first) {
  check_t(C.rows(), t);
  check_order(C.rows(), order, first);
  const Codec cd(p, fr);
  // Every vertex in index order (sequential), minus the rare tie-group members (first == 0).
  std::int64_t c = 0;
  for (Eigen::Index i = 0; i < C.rows(); ++i)
    for (int a = 0; a < 3; ++a) c += cd.free_bits(cd.get(C(i, a), a), t[i]);
  for (Eigen::Index k = 0; k < order.size(); ++k) {
    if (first[k]) continue;
    const Index i = order[k];
    for (int a = 0; a < 3; ++a) c -= cd.free_bits(cd.get(C(i, a), a), t[i]);
  }
  return c;
}

MatrixX3dR stego_write_bits(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                            StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                            const Eigen::Ref<const VectorXb>& first, const std::vector<std::uint8_t>& bits,
                            std::int64_t nbits) {
  check_t(C.rows(), t);
  check_order(C.rows(), order, first);
  if (nbits < 0 || static_cast<std::int64_t>(bits.size()) * 8 < nbits) throw MeshError("bit buffer shorter than nbits");
  const Codec cd(p, fr);
  MatrixX3dR out = C;
  std::int64_t pos = 0, group_start = 0;
  for (Eigen::Index k = 0; k < order.size(); ++k) {
    const Index i = order[k];
    if (first[k]) group_start = pos;
    std::int64_t b = group_start;  // members replay their leader's bits
    for (int a = 0; a < 3; ++a) {
      Word w = cd.get(C(i, a), a);
      const int f = cd.free_bits(w, t[i]);
      for (int q = f; q >= 1 && b < nbits; --q, ++b) {  // most significant message bit first
        const std::uint64_t m = std::uint64_t{1} << q;
        w.bits = get_bit(bits, b) ? (w.bits | m) : (w.bits & ~m);
      }
      if (f > 0) out(i, a) = cd.put(w, a);
      if (b >= nbits) b = nbits;
    }
    if (first[k]) pos = b;
  }
  return out;
}

std::vector<std::uint8_t> stego_read_bits(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                                          StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                                          const Eigen::Ref<const VectorXb>& first, std::int64_t nbits) {
  check_t(C.rows(), t);
  check_order(C.rows(), order, first);
  const Codec cd(p, fr);
  std::vector<std::uint8_t> out(static_cast<std::size_t>((std::max<std::int64_t>(nbits, 0) + 7) / 8), 0);
  std::int64_t b = 0;
  for (Eigen::Index k = 0; k < order.size() && b < nbits; ++k) {
    if (!first[k]) continue;
    const Index i = order[k];
    for (int a = 0; a < 3 && b < nbits; ++a) {
      const Word w = cd.get(C(i, a), a);
      const int f = cd.free_bits(w, t[i]);
      for (int q = f; q >= 1 && b < nbits; --q, ++b) set_bit(out, b, static_cast<int>((w.bits >> q) & 1u));
    }
  }
  return out;
}

std::int64_t stego_lsb_capacity(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                                const Eigen::Ref<const VectorXb>& first, const Eigen::Ref<const VectorXi>& order) {
  check_order(C.rows(), order, first);
  const Codec cd(p, fr);
  std::int64_t c = 0;
  for (Eigen::Index i = 0; i < C.rows(); ++i)
    for (int a = 0; a < 3; ++a) c += cd.get(C(i, a), a).has ? 1 : 0;
  for (Eigen::Index k = 0; k < order.size(); ++k)
    if (!first[k])
      for (int a = 0; a < 3; ++a) c -= cd.get(C(order[k], a), a).has ? 1 : 0;
  return c;
}

MatrixX3dR stego_write_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                           const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first,
                           const std::vector<std::uint8_t>& bits, std::int64_t nbits) {
  check_order(C.rows(), order, first);
  if (nbits < 0 || static_cast<std::int64_t>(bits.size()) * 8 < nbits) throw MeshError("bit buffer shorter than nbits");
  const Codec cd(p, fr);
  MatrixX3dR out = C;
  std::int64_t pos = 0, group_start = 0;
  for (Eigen::Index k = 0; k < order.size(); ++k) {
    if (first[k]) {
      if (pos >= nbits) break;  // the rest keeps its own LSBs
      group_start = pos;
    }
    const Index i = order[k];
    std::int64_t b = group_start;
    for (int a = 0; a < 3 && b < nbits; ++a) {
      Word w = cd.get(C(i, a), a);
      if (!w.has) continue;
      w.bits = get_bit(bits, b) ? (w.bits | 1u) : (w.bits & ~std::uint64_t{1});
      ++b;
      out(i, a) = cd.put(w, a);
    }
    if (first[k]) pos = b;
  }
  return out;
}

std::vector<std::uint8_t> stego_read_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                                         const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first,
                                         std::int64_t nbits) {
  check_order(C.rows(), order, first);
  const Codec cd(p, fr);
  std::vector<std::uint8_t> out(static_cast<std::size_t>((std::max<std::int64_t>(nbits, 0) + 7) / 8), 0);
  std::int64_t b = 0;
  for (Eigen::Index k = 0; k < order.size() && b < nbits; ++k) {
    if (!first[k]) continue;
    for (int a = 0; a < 3 && b < nbits; ++a) {
      const Word w = cd.get(C(order[k], a), a);
      if (!w.has) continue;
      set_bit(out, b++, static_cast<int>(w.bits & 1u));
    }
  }
  return out;
}

}  // namespace meshmark
