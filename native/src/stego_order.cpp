// pi_1 / pi_2 of thesis §4.3.2: projection order on the first principal axis, permutation invariant.
#include "meshmark/stego_order.h"
#include "meshmark/error.h"
#include "meshmark/huge_pages.h"
#include "meshmark/pca.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

namespace meshmark {

namespace {
using i128 = __int128;

inline std::uint64_t bits_of(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, 8);
  return b;
}
// Per-vertex value -> fixed point integer (deterministic, the same for every vertex order).
// llround(x * pow2) (pow2 = 2^scale: exact product), inline: |y| < 2^62 here, so the truncation and
// y - trunc(y) are exact and rounding half away from zero is one comparison.
inline std::int64_t fix(double x, double pow2) {
  const double y = x * pow2;
  std::int64_t r = static_cast<std::int64_t>(y);
  const double f = y - static_cast<double>(r);
  return r + (f >= 0.5) - (f <= -0.5);
}
inline long double unfix(i128 s, int scale) { return std::ldexp(static_cast<long double>(s), -scale); }
// n zero-initialised elements, huge pages advised before the first touch (huge_pages.h)
template <class T>
std::vector<T> big_vector(std::size_t n) {
  std::vector<T> v;
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
  v.resize(n);
  return v;
}
inline std::uint64_t mix(std::uint64_t x) {  // splitmix64 finalizer
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
}  // namespace

StegoOrder stego_order(const Eigen::Ref<const MatrixX3dR>& Q0, const Eigen::Ref<const VectorXi>& t, int E,
                       const Eigen::Vector3d& o, const Polygons& P) {
  // Relative to the frame origin (exact: Q - o is on the same grid and smaller than 2^E).
  const Eigen::Index n = Q0.rows();
  MatrixX3dR Q(n, 3);
  advise_huge_pages(Q.data(), static_cast<std::size_t>(n) * 3 * sizeof(double));
  Q = Q0.rowwise() - o.transpose();
  if (n == 0) throw MeshError("empty mesh: no vertices to order");
  if (t.size() != n) throw MeshError("t must have one cell exponent per vertex");
  if (E < -300 || E > 300) throw MeshError("coordinates out of the range of the stego orderings (|x| ~ 2^" + std::to_string(E) + ")");
  // Centroid: exact sum of the coordinates on the grid 2^(E-40) (|x| <= 2^E, so |X| <= 2^40).
  const int sc1 = 40 - E;
  const double p1 = std::ldexp(1.0, sc1);
  i128 S[3] = {0, 0, 0};
  for (Eigen::Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) S[a] += fix(Q(i, a), p1);
  Eigen::Vector3d mu;
  for (int a = 0; a < 3; ++a) mu[a] = static_cast<double>(unfix(S[a], sc1) / static_cast<long double>(n));
  // Covariance: |d| <= 2^(E+1), |d_a d_b| <= 2^(2E+2): products on the grid 2^(2E+2-60).
  const int sc2 = 58 - 2 * E;
  const double p2 = std::ldexp(1.0, sc2);
  i128 C[6] = {0, 0, 0, 0, 0, 0};
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d0 = Q(i, 0) - mu[0], d1 = Q(i, 1) - mu[1], d2 = Q(i, 2) - mu[2];
    C[0] += fix(d0 * d0, p2);
    C[1] += fix(d0 * d1, p2);
    C[2] += fix(d0 * d2, p2);
    C[3] += fix(d1 * d1, p2);
    C[4] += fix(d1 * d2, p2);
    C[5] += fix(d2 * d2, p2);
  }
  const long double inv = 1.0L / static_cast<long double>(n);
  Eigen::Matrix3d M;
  M(0, 0) = static_cast<double>(unfix(C[0], sc2) * inv);
  M(0, 1) = M(1, 0) = static_cast<double>(unfix(C[1], sc2) * inv);
  M(0, 2) = M(2, 0) = static_cast<double>(unfix(C[2], sc2) * inv);
  M(1, 1) = static_cast<double>(unfix(C[3], sc2) * inv);
  M(1, 2) = M(2, 1) = static_cast<double>(unfix(C[4], sc2) * inv);
  M(2, 2) = static_cast<double>(unfix(C[5], sc2) * inv);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M);
  Eigen::Vector3d q = es.eigenvectors().col(2).normalized();  // largest eigenvalue (ascending order)
  const double lambda = std::max(0.0, es.eigenvalues()[2]);
  // Projections and the sign rule of meshmark::pca (third moment; exact fixed-point sum of p^3,
  // |p| <= sqrt(3) 2^(E+1) < 2^(E+2), |p^3| < 2^(3E+6)).
  std::vector<double> proj = big_vector<double>(static_cast<std::size_t>(n));
  const int sc3 = 56 - 3 * E;
  const double p3 = std::ldexp(1.0, sc3);
  i128 m3s = 0;
  double pmin = 0, pmax = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double p = (Q(i, 0) - mu[0]) * q[0] + (Q(i, 1) - mu[1]) * q[1] + (Q(i, 2) - mu[2]) * q[2];
    proj[static_cast<std::size_t>(i)] = p;
    m3s += fix(p * p * p, p3);
    if (i == 0 || p < pmin) pmin = p;
    if (i == 0 || p > pmax) pmax = p;
  }
  const double m3 = static_cast<double>(unfix(m3s, sc3) * inv);
  if (pca_axis_sign(m3, pmin, pmax, lambda, q) < 0) {
    q = -q;
    for (double& p : proj) p = -p;  // exact: x . (-q) == -(x . q) in IEEE arithmetic
  }
  StegoOrder out;
  out.axis = q;
  out.centroid = mu + o;
  // Sort by kp, the order-preserving integer image of the projection (so -0.0 sorts before +0.0),
  // ties by vertex index (a stable sort). Done as: a stable LSD radix sort (3 passes of 11 bits, the
  // buckets stay in L1) on k32 = floor((p - pmin) 2^32 / (pmax - pmin)), which is non-decreasing in p
  // (each operation is monotone under rounding), then the runs of equal k32 by (kp, index).
  const std::size_t N = static_cast<std::size_t>(n);
  std::vector<std::uint64_t> kp = big_vector<std::uint64_t>(N);
  std::vector<std::uint32_t> k32 = big_vector<std::uint32_t>(N), kt = big_vector<std::uint32_t>(N);
  std::vector<Index> ord = big_vector<Index>(N), ot = big_vector<Index>(N);
  double lo = proj[0], hi = proj[0];
  for (double p : proj) lo = std::min(lo, p), hi = std::max(hi, p);
  double scale = 4294967295.0 / (hi - lo);
  if (!std::isfinite(scale)) scale = 0;  // all equal (or a span too small to divide by)
  for (std::size_t i = 0; i < N; ++i) {
    const std::uint64_t b = bits_of(proj[i]);
    kp[i] = (b >> 63) ? ~b : (b | (std::uint64_t{1} << 63));
    const double x = (proj[i] - lo) * scale;
    k32[i] = x >= 4294967295.0 ? 0xffffffffu : static_cast<std::uint32_t>(x);
    ord[i] = static_cast<Index>(i);
  }
  constexpr int kBits = 11, kPasses = 3;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  std::vector<std::size_t> count(kPasses * kBuckets, 0);
  for (std::size_t i = 0; i < N; ++i)
    for (int pass = 0; pass < kPasses; ++pass) ++count[pass * kBuckets + ((k32[i] >> (kBits * pass)) & (kBuckets - 1))];
  for (int pass = 0; pass < kPasses; ++pass) {
    const int shift = kBits * pass;
    std::size_t* c = count.data() + pass * kBuckets;
    if (c[(k32[0] >> shift) & (kBuckets - 1)] == N) continue;  // one digit value: nothing to do
    std::size_t sum = 0;
    for (std::size_t d = 0; d < kBuckets; ++d) {
      const std::size_t x = c[d];
      c[d] = sum;
      sum += x;
    }
    for (std::size_t i = 0; i < N; ++i) {
      const std::size_t dst = c[(k32[i] >> shift) & (kBuckets - 1)]++;
      kt[dst] = k32[i];
      ot[dst] = ord[i];
    }
    k32.swap(kt);
    ord.swap(ot);
  }
  for (std::size_t k = 0; k < N;) {
    std::size_t e = k + 1;
    while (e < N && k32[e] == k32[k]) ++e;
    if (e - k > 1)
      std::sort(ord.begin() + static_cast<std::ptrdiff_t>(k), ord.begin() + static_cast<std::ptrdiff_t>(e),
                [&](Index a, Index b) { return kp[a] != kp[b] ? kp[a] < kp[b] : a < b; });
    k = e;
  }
  {  // kp in sorted order, for the runs below
    std::vector<std::uint64_t> ks = big_vector<std::uint64_t>(N);
    for (std::size_t j = 0; j < N; ++j) ks[j] = kp[static_cast<std::size_t>(ord[j])];
    kp.swap(ks);
  }
  // Runs of equal projections: sort by (x, y, z, t); only vertices still tied after that need the
  // neighbourhood hash (order-free wrapping sums over their faces), computed for them alone.
  auto qt_less = [&](Index a, Index b) {
    for (int c = 0; c < 3; ++c) {
      const std::uint64_t xa = bits_of(Q0(a, c)), xb = bits_of(Q0(b, c));
      if (xa != xb) return xa < xb;
    }
    return t[a] < t[b];
  };
  std::vector<std::uint8_t> tied;
  for (std::size_t k = 0; k < kp.size();) {
    std::size_t e = k + 1;
    while (e < kp.size() && kp[e] == kp[k]) ++e;
    if (e - k > 1) {
      std::sort(ord.begin() + static_cast<std::ptrdiff_t>(k), ord.begin() + static_cast<std::ptrdiff_t>(e), qt_less);
      for (std::size_t j = k + 1; j < e; ++j)
        if (!qt_less(ord[j - 1], ord[j])) {
          if (tied.empty()) tied.assign(static_cast<std::size_t>(n), 0);
          tied[static_cast<std::size_t>(ord[j - 1])] = tied[static_cast<std::size_t>(ord[j])] = 1;
        }
    }
    k = e;
  }
  std::vector<std::uint64_t> nb;
  if (!tied.empty()) {
    auto h = [&](Index i) {
      return mix(mix(mix(mix(bits_of(Q0(i, 0))) ^ bits_of(Q0(i, 1))) ^ bits_of(Q0(i, 2))) ^
                 static_cast<std::uint64_t>(static_cast<std::uint32_t>(t[i])));
    };
    nb.assign(static_cast<std::size_t>(n), 0);
    for (Offset f = 0; f < P.n_faces(); ++f) {
      bool any = false;
      for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) {
        const Index v = P.indices[c];
        if (v < 0 || v >= n) throw MeshError("face " + std::to_string(f) + " has a vertex out of range");
        any = any || tied[static_cast<std::size_t>(v)];
      }
      if (!any) continue;
      std::uint64_t sum = 0;
      for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) sum += h(P.indices[c]);
      for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) {
        const Index v = P.indices[c];
        if (tied[static_cast<std::size_t>(v)]) nb[static_cast<std::size_t>(v)] += sum - h(v);
      }
    }
  }
  auto rest_less = [&](Index a, Index b) {
    if (qt_less(a, b)) return true;
    if (qt_less(b, a)) return false;
    return !nb.empty() && nb[static_cast<std::size_t>(a)] < nb[static_cast<std::size_t>(b)];
  };
  out.order.resize(n);
  out.first.resize(n);
  for (std::size_t k = 0; k < kp.size();) {
    std::size_t e = k + 1;
    while (e < kp.size() && kp[e] == kp[k]) ++e;
    if (e - k > 1 && !nb.empty())
      std::sort(ord.begin() + static_cast<std::ptrdiff_t>(k), ord.begin() + static_cast<std::ptrdiff_t>(e), rest_less);
    for (std::size_t j = k; j < e; ++j) {
      out.order[static_cast<Eigen::Index>(j)] = ord[j];
      out.first[static_cast<Eigen::Index>(j)] = (j == k || rest_less(ord[j - 1], ord[j])) ? 1 : 0;
    }
    k = e;
  }
  return out;
}

}  // namespace meshmark
