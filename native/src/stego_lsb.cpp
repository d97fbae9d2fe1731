// §4.3.2 bit layout: quantization, message bits and the LSB stream (see stego_lsb.h).
#include "meshmark/stego_lsb.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

namespace meshmark {

namespace {

// (n, 3) output with huge pages advised before it is filled (huge_pages.h): fewer page faults.
MatrixX3dR big_matrix(Eigen::Index n) {
  MatrixX3dR out(n, 3);
  advise_huge_pages(out.data(), static_cast<std::size_t>(n) * 3 * sizeof(double));
  return out;
}

// One coordinate word: its low bits, the weight exponent of bit 0, whether it can carry.
struct Word {
  std::uint64_t bits = 0;
  int u = 0;
  bool has = false;
};

// x * 2^k: std::ldexp's correctly rounded value, as one multiplication when 2^k is a normal double
// (then the product is the same correctly rounded value); ldexp otherwise.
struct Pow2 {
  int k;
  double m;
  explicit Pow2(int k_) : k(k_), m(k_ >= -1022 && k_ <= 1023 ? std::ldexp(1.0, k_) : 0.0) {}
  double operator()(double x) const { return m != 0 ? x * m : std::ldexp(x, k); }
};

// The word types of stego_lsb.h, one template: Fixed32 (FloatT = void) and the IEEE patterns of
// float / double (W = the mantissa width, u = exponent field - bias - W).
template <StegoPrecision P>
struct Codec {
  using FloatT = std::conditional_t<P == StegoPrecision::Float32, float, double>;
  using BitsT = std::conditional_t<P == StegoPrecision::Float32, std::uint32_t, std::uint64_t>;
  static constexpr bool kFixed = P == StegoPrecision::Fixed32;
  static constexpr int kMant = std::numeric_limits<FloatT>::digits - 1;                   // 23, 52
  static constexpr int kBias = std::numeric_limits<FloatT>::max_exponent - 1 + kMant;    // 150, 1075
  static constexpr std::uint64_t kExpMask = (std::uint64_t{1} << (8 * sizeof(FloatT) - 1 - kMant)) - 1;
  static constexpr int W = kFixed ? 31 : kMant;  // modifiable width
  int s;  // Fixed32 unit exponent
  Eigen::Vector3d o;
  Pow2 down, up;

  explicit Codec(const StegoFrame& fr) : s(fr.E - 32), o(fr.o), down(-(fr.E - 32)), up(fr.E - 32) {}
  Word get(double x, int a) const {
    Word w;
    if constexpr (kFixed) {
      w.bits = static_cast<std::uint64_t>(down(x - o[a]));
      w.u = s;
      w.has = true;
    } else {
      const FloatT f = static_cast<FloatT>(x);
      BitsT b;
      std::memcpy(&b, &f, sizeof b);
      const int ef = static_cast<int>((b >> kMant) & kExpMask);
      w.bits = b;
      w.u = ef - kBias;
      w.has = ef != 0;
    }
    return w;
  }
  double put(const Word& w, int a) const {
    if constexpr (kFixed) {
      return o[a] + up(static_cast<double>(w.bits));
    } else {
      const BitsT b = static_cast<BitsT>(w.bits);
      FloatT f;
      std::memcpy(&f, &b, sizeof f);
      return static_cast<double>(f);
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

// fn(codec) with the codec of the precision
template <class Fn>
decltype(auto) with_codec(StegoPrecision p, const StegoFrame& fr, Fn&& fn) {
  switch (p) {
    case StegoPrecision::Fixed32: return fn(Codec<StegoPrecision::Fixed32>(fr));
    case StegoPrecision::Float32: return fn(Codec<StegoPrecision::Float32>(fr));
    case StegoPrecision::Float64:
    default: return fn(Codec<StegoPrecision::Float64>(fr));
  }
}

// Bit streams, MSB first. The buffers carry 8 bytes of zero padding so that 64-bit loads never run
// past them; a field of cnt <= 57 bits at bit b spans at most 8 bytes.
inline std::uint64_t load_be64(const std::uint8_t* p) {
  std::uint64_t x = 0;
  for (int j = 0; j < 8; ++j) x = (x << 8) | p[j];
  return x;
}
inline std::uint64_t get_bits(const std::vector<std::uint8_t>& buf, std::int64_t b, int cnt) {
  if (cnt == 0) return 0;
  const std::uint64_t x = load_be64(buf.data() + (b >> 3)) << (b & 7);
  return x >> (64 - cnt);
}
inline void or_bits(std::vector<std::uint8_t>& buf, std::int64_t b, int cnt, std::uint64_t v) {
  if (cnt == 0) return;
  const std::uint64_t x = v << (64 - cnt - (b & 7));
  std::uint8_t* p = buf.data() + (b >> 3);
  for (int j = 0; j < 8; ++j) p[j] |= static_cast<std::uint8_t>(x >> (56 - 8 * j));
}
inline std::vector<std::uint8_t> padded(const std::vector<std::uint8_t>& bits) {
  std::vector<std::uint8_t> out(bits.size() + 8, 0);
  std::copy(bits.begin(), bits.end(), out.begin());
  return out;
}
inline std::uint64_t low_mask(int cnt) { return cnt >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << cnt) - 1; }

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
  MatrixX3dR out = big_matrix(V.rows());
  const int s = fr.E - 32;
  const Pow2 down(-s), up(s);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int a = 0; a < 3; ++a) {
      const double x = V(i, a);
      switch (p) {
        case StegoPrecision::Fixed32: {
          double n = std::floor(down(x - fr.o[a]));
          n = std::min(std::max(n, 0.0), 4294967295.0);
          out(i, a) = fr.o[a] + up(n);
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
  return with_codec(p, fr, [&](const auto& cd) {
    MatrixX3dR out = big_matrix(C.rows());
    for (Eigen::Index i = 0; i < C.rows(); ++i)
      for (int a = 0; a < 3; ++a) {
        Word w = cd.get(C(i, a), a);
        const int z = cd.zero_bits(w, t[i]);
        if (z > 0) w.bits &= ~((std::uint64_t{1} << z) - 1);
        out(i, a) = w.has ? cd.put(w, a) : C(i, a);
      }
    return out;
  });
}

MatrixX3dR stego_clear_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr) {
  return with_codec(p, fr, [&](const auto& cd) {
    MatrixX3dR out = big_matrix(C.rows());
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
  });
}

std::int64_t stego_capacity(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                            StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                            const Eigen::Ref<const VectorXb>& first) {
  check_t(C.rows(), t);
  check_order(C.rows(), order, first);
  return with_codec(p, fr, [&](const auto& cd) {
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
  });
}

MatrixX3dR stego_write_bits(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                            StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                            const Eigen::Ref<const VectorXb>& first, const std::vector<std::uint8_t>& bits,
                            std::int64_t nbits) {
  check_t(C.rows(), t);
  check_order(C.rows(), order, first);
  if (nbits < 0 || static_cast<std::int64_t>(bits.size()) * 8 < nbits) throw MeshError("bit buffer shorter than nbits");
  const std::vector<std::uint8_t> buf = padded(bits);
  return with_codec(p, fr, [&](const auto& cd) {
    MatrixX3dR out = big_matrix(C.rows());
    out = C;
    std::int64_t pos = 0, group_start = 0;
    for (Eigen::Index k = 0; k < order.size(); ++k) {
      const Index i = order[k];
      if (first[k]) group_start = pos;
      std::int64_t b = group_start;  // members replay their leader's bits
      for (int a = 0; a < 3; ++a) {
        Word w = cd.get(C(i, a), a);
        const int f = cd.free_bits(w, t[i]);
        // bits f, f-1, .. (most significant message bit first) take the next cnt stream bits
        const int cnt = static_cast<int>(std::min<std::int64_t>(f, std::max<std::int64_t>(0, nbits - b)));
        if (cnt > 0) {
          const int lo = f - cnt + 1;
          w.bits = (w.bits & ~(low_mask(cnt) << lo)) | (get_bits(buf, b, cnt) << lo);
          b += cnt;
        }
        if (f > 0) out(i, a) = cd.put(w, a);
      }
      if (first[k]) pos = b;
    }
    return out;
  });
}

std::vector<std::uint8_t> stego_read_bits(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                                          StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                                          const Eigen::Ref<const VectorXb>& first, std::int64_t nbits) {
  check_t(C.rows(), t);
  check_order(C.rows(), order, first);
  const std::int64_t nb = std::max<std::int64_t>(nbits, 0);
  std::vector<std::uint8_t> out(static_cast<std::size_t>((nb + 7) / 8 + 8), 0);
  with_codec(p, fr, [&](const auto& cd) {
    std::int64_t b = 0;
    for (Eigen::Index k = 0; k < order.size() && b < nb; ++k) {
      if (!first[k]) continue;
      const Index i = order[k];
      for (int a = 0; a < 3 && b < nb; ++a) {
        const Word w = cd.get(C(i, a), a);
        const int f = cd.free_bits(w, t[i]);
        const int cnt = static_cast<int>(std::min<std::int64_t>(f, nb - b));  // bits f .. f - cnt + 1
        if (cnt > 0) or_bits(out, b, cnt, (w.bits >> (f - cnt + 1)) & low_mask(cnt));
        b += cnt;
      }
    }
    return 0;
  });
  out.resize(static_cast<std::size_t>((nb + 7) / 8));
  return out;
}

std::int64_t stego_lsb_capacity(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                                const Eigen::Ref<const VectorXb>& first, const Eigen::Ref<const VectorXi>& order) {
  check_order(C.rows(), order, first);
  return with_codec(p, fr, [&](const auto& cd) {
    std::int64_t c = 0;
    for (Eigen::Index i = 0; i < C.rows(); ++i)
      for (int a = 0; a < 3; ++a) c += cd.get(C(i, a), a).has ? 1 : 0;
    for (Eigen::Index k = 0; k < order.size(); ++k)
      if (!first[k])
        for (int a = 0; a < 3; ++a) c -= cd.get(C(order[k], a), a).has ? 1 : 0;
    return c;
  });
}

MatrixX3dR stego_write_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                           const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first,
                           const std::vector<std::uint8_t>& bits, std::int64_t nbits) {
  check_order(C.rows(), order, first);
  if (nbits < 0 || static_cast<std::int64_t>(bits.size()) * 8 < nbits) throw MeshError("bit buffer shorter than nbits");
  return with_codec(p, fr, [&](const auto& cd) {
    MatrixX3dR out = big_matrix(C.rows());
    out = C;
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
  });
}

std::vector<std::uint8_t> stego_read_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                                         const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first,
                                         std::int64_t nbits) {
  check_order(C.rows(), order, first);
  std::vector<std::uint8_t> out(static_cast<std::size_t>((std::max<std::int64_t>(nbits, 0) + 7) / 8), 0);
  with_codec(p, fr, [&](const auto& cd) {
    std::int64_t b = 0;
    for (Eigen::Index k = 0; k < order.size() && b < nbits; ++k) {
      if (!first[k]) continue;
      for (int a = 0; a < 3 && b < nbits; ++a) {
        const Word w = cd.get(C(order[k], a), a);
        if (!w.has) continue;
        set_bit(out, b++, static_cast<int>(w.bits & 1u));
      }
    }
    return 0;
  });
  return out;
}

}  // namespace meshmark
