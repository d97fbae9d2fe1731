// pi_1 / pi_2 of thesis §4.3.2: projection order on the first principal axis, permutation invariant.
#include "meshmark/stego_order.h"
#include "meshmark/error.h"
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
inline std::int64_t fix(double x, int scale) { return std::llround(std::ldexp(x, scale)); }
inline long double unfix(i128 s, int scale) { return std::ldexp(static_cast<long double>(s), -scale); }
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
  MatrixX3dR Q = Q0.rowwise() - o.transpose();
  const Eigen::Index n = Q.rows();
  if (n == 0) throw MeshError("empty mesh: no vertices to order");
  if (t.size() != n) throw MeshError("t must have one cell exponent per vertex");
  // Centroid: exact sum of the coordinates on the grid 2^(E-40) (|x| <= 2^E, so |X| <= 2^40).
  const int sc1 = 40 - E;
  i128 S[3] = {0, 0, 0};
  for (Eigen::Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) S[a] += fix(Q(i, a), sc1);
  Eigen::Vector3d mu;
  for (int a = 0; a < 3; ++a) mu[a] = static_cast<double>(unfix(S[a], sc1) / static_cast<long double>(n));
  // Covariance: |d| <= 2^(E+1), |d_a d_b| <= 2^(2E+2): products on the grid 2^(2E+2-60).
  const int sc2 = 58 - 2 * E;
  i128 C[6] = {0, 0, 0, 0, 0, 0};
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d0 = Q(i, 0) - mu[0], d1 = Q(i, 1) - mu[1], d2 = Q(i, 2) - mu[2];
    C[0] += fix(d0 * d0, sc2);
    C[1] += fix(d0 * d1, sc2);
    C[2] += fix(d0 * d2, sc2);
    C[3] += fix(d1 * d1, sc2);
    C[4] += fix(d1 * d2, sc2);
    C[5] += fix(d2 * d2, sc2);
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
  std::vector<double> proj(static_cast<std::size_t>(n));
  const int sc3 = 56 - 3 * E;
  i128 m3s = 0;
  double pmin = 0, pmax = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double p = (Q(i, 0) - mu[0]) * q[0] + (Q(i, 1) - mu[1]) * q[1] + (Q(i, 2) - mu[2]) * q[2];
    proj[static_cast<std::size_t>(i)] = p;
    m3s += fix(p * p * p, sc3);
    if (i == 0 || p < pmin) pmin = p;
    if (i == 0 || p > pmax) pmax = p;
  }
  const double m3 = static_cast<double>(unfix(m3s, sc3) * inv);
  if (pca_axis_sign(m3, pmin, pmax, lambda, q) < 0) {
    q = -q;
    for (double& p : proj) p = -p;  // exact: x . (-q) == -(x . q) in IEEE arithmetic
  }
  // Neighbourhood hash (order-free: wrapping sums).
  std::vector<std::uint64_t> h(static_cast<std::size_t>(n)), nb(static_cast<std::size_t>(n), 0);
  for (Eigen::Index i = 0; i < n; ++i)
    h[static_cast<std::size_t>(i)] =
        mix(mix(mix(mix(bits_of(Q0(i, 0))) ^ bits_of(Q0(i, 1))) ^ bits_of(Q0(i, 2))) ^ static_cast<std::uint64_t>(t[i]));
  for (Offset f = 0; f < P.n_faces(); ++f) {
    std::uint64_t sum = 0;
    for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) {
      const Index v = P.indices[c];
      if (v < 0 || v >= n) throw MeshError("face " + std::to_string(f) + " has a vertex out of range");
      sum += h[static_cast<std::size_t>(v)];
    }
    for (Offset c = P.offsets[f]; c < P.offsets[f + 1]; ++c) {
      const auto v = static_cast<std::size_t>(P.indices[c]);
      nb[v] += sum - h[v];
    }
  }
  StegoOrder out;
  out.axis = q;
  out.centroid = mu + o;
  // Sort contiguous keys (cache friendly): projection, coordinate bit patterns, t, neighbourhood hash.
  struct Key {
    double p;
    std::uint64_t x, y, z, nb;
    Index t, i;
  };
  std::vector<Key> keys(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    keys[static_cast<std::size_t>(i)] = {proj[static_cast<std::size_t>(i)], bits_of(Q0(i, 0)), bits_of(Q0(i, 1)),
                                         bits_of(Q0(i, 2)), nb[static_cast<std::size_t>(i)], t[i], static_cast<Index>(i)};
  auto key_less = [](const Key& a, const Key& b) {
    if (a.p < b.p) return true;
    if (b.p < a.p) return false;
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    if (a.z != b.z) return a.z < b.z;
    if (a.t != b.t) return a.t < b.t;
    return a.nb < b.nb;
  };
  std::sort(keys.begin(), keys.end(), key_less);
  out.order.resize(n);
  out.first.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    out.order[k] = keys[kk].i;
    out.first[k] = (k == 0 || key_less(keys[kk - 1], keys[kk])) ? 1 : 0;
  }
  return out;
}

}  // namespace meshmark
