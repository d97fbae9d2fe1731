#include "meshmark/laplacian_carrier.h"
#include "meshmark/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>
#include <string>

namespace meshmark {

namespace {

// Per vertex: the uniform Laplacian L_i = sum_{j in N(i)} (x_i - x_j) (eqs. 7.1.2-7.1.3) and the sum of the
// incident edge lengths, side by side (one cache line per vertex and edge end), and the valence.
struct RingSums {
  std::vector<double> buffer;  // n rows of (Lx, Ly, Lz, sum of edge lengths), rows 64-byte aligned pairs
  double* acc = nullptr;
  std::vector<Index> deg;
  void zero(Eigen::Index n) {
    buffer.assign(static_cast<size_t>(4 * n + 8), 0.0);
    const auto addr = reinterpret_cast<std::uintptr_t>(buffer.data());
    acc = buffer.data() + ((64 - addr % 64) % 64) / sizeof(double);  // no row straddles two cache lines
    deg.assign(static_cast<size_t>(n), 0);
  }
  double* row(Eigen::Index i) { return acc + 4 * i; }
  const double* row(Eigen::Index i) const { return acc + 4 * i; }
};

LaplacianCarrierField finish(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                             LaplacianCarrier kind, double scale, bool with_direction, double compress,
                             const RingSums& S);

void check(LaplacianCarrier kind, double scale, double compress, Eigen::Index n_tri, Eigen::Index n_edges) {
  const int k = static_cast<int>(kind);
  if (k < 0 || k > 5) throw MeshError("unknown Laplacian carrier " + std::to_string(k));
  if (!(scale > 0)) throw MeshError("carrier scale must be > 0");
  if (!(compress >= 0)) throw MeshError("carrier compression must be >= 0");
  const bool tri = kind == LaplacianCarrier::Normal || kind == LaplacianCarrier::CotNormal ||
                   kind == LaplacianCarrier::NormalGlobal || kind == LaplacianCarrier::CotLocal;
  if (tri && n_tri == 0 && n_edges > 0) throw MeshError("the normal and cotangent carriers need the mesh's triangles");
}

}  // namespace

LaplacianCarrierField laplacian_carrier(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX2iR>& E,
                                        const Eigen::Ref<const MatrixX3iR>& T, LaplacianCarrier kind, double scale,
                                        bool with_direction, double compress) {
  check(kind, scale, compress, T.rows(), E.rows());
  const Eigen::Index n = V.rows();
  RingSums S;
  S.zero(n);
  // The pass below reads V(a) in order but V(b) at random; a fresh V (the extraction's welded copy) is
  // not in the cache yet, and every random row would wait for memory. One sequential read first lets
  // the hardware prefetcher bring it in (the thesis path's L = -eps V does the same by the way).
  double touch = 0;
  for (Eigen::Index i = 0; i < n; ++i) touch += V(i, 0);
  asm volatile("" : : "x"(touch));
  for (Eigen::Index e = 0; e < E.rows(); ++e) {  // one pass over the edges (scattered to both ends)
    const Index a = E(e, 0), b = E(e, 1);
    const double x = V(a, 0) - V(b, 0), y = V(a, 1) - V(b, 1), z = V(a, 2) - V(b, 2);
    const double l = std::sqrt(x * x + y * y + z * z);
    double *pa = S.row(a), *pb = S.row(b);
    pa[0] += x, pa[1] += y, pa[2] += z, pa[3] += l;
    pb[0] -= x, pb[1] -= y, pb[2] -= z, pb[3] += l;
    ++S.deg[a], ++S.deg[b];
  }
  return finish(V, T, kind, scale, with_direction, compress, S);
}

LaplacianCarrierField laplacian_carrier(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A,
                                        const Eigen::Ref<const MatrixX3iR>& T, LaplacianCarrier kind, double scale,
                                        bool with_direction, double compress) {
  check(kind, scale, compress, T.rows(), static_cast<Eigen::Index>(A.nbr.size()));
  const Eigen::Index n = V.rows();
  if (kind == LaplacianCarrier::Thesis || kind == LaplacianCarrier::Local) {
    // One pass, no per-vertex sums kept (the embedding calls this every round): vertices in increasing
    // order gather L_i; each edge length is computed once (j > i) and added to both ends, so that
    // when v_i is reached every j < i has already added its share and l_i is complete.
    const bool local = kind == LaplacianCarrier::Local;
    Eigen::VectorXd elen = Eigen::VectorXd::Zero(local ? n : 0);
    LaplacianCarrierField out;
    out.value.resize(n);
    if (with_direction) out.direction.resize(n, 3), out.gain.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      double x = 0, y = 0, z = 0, l = 0;
      const double xi = V(i, 0), yi = V(i, 1), zi = V(i, 2);
      for (Offset k = A.ptr[i]; k < A.ptr[i + 1]; ++k) {
        const Index j = A.nbr[k];
        const double dx = xi - V(j, 0), dy = yi - V(j, 1), dz = zi - V(j, 2);
        x += dx, y += dy, z += dz;
        if (local && j > i) {
          const double e = std::sqrt(dx * dx + dy * dy + dz * dz);
          l += e;
          elen[j] += e;
        }
      }
      const double deg = static_cast<double>(A.ptr[i + 1] - A.ptr[i]);
      const double ell = local ? (elen[i] + l) / std::max(deg, 1.0) : scale;
      out.value[i] = 0;
      if (with_direction) out.direction.row(i).setZero(), out.gain[i] = 0;
      if (deg == 0 || !(ell > 0)) continue;
      const double d = std::sqrt(x * x + y * y + z * z);  // eq. 7.1.5
      double v = d / ell;
      if (with_direction && d > 0) out.direction(i, 0) = x / d, out.direction(i, 1) = y / d,
                                   out.direction(i, 2) = z / d, out.gain[i] = ell;
      if (compress > 0) {
        if (with_direction) out.gain[i] *= std::sqrt(v * v + compress * compress);
        v = std::asinh(v / compress);
      }
      out.value[i] = v;
    }
    return out;
  }
  RingSums S;
  S.zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {  // L gathered per vertex; each edge length computed once (j > i)
    double x = 0, y = 0, z = 0, l = 0;
    const double xi = V(i, 0), yi = V(i, 1), zi = V(i, 2);
    for (Offset k = A.ptr[i]; k < A.ptr[i + 1]; ++k) {
      const Index j = A.nbr[k];
      const double dx = xi - V(j, 0), dy = yi - V(j, 1), dz = zi - V(j, 2);
      x += dx, y += dy, z += dz;
      if (j > i) {
        const double e = std::sqrt(dx * dx + dy * dy + dz * dz);
        l += e;
        S.row(j)[3] += e;
      }
    }
    double* r = S.row(i);
    r[0] = x, r[1] = y, r[2] = z, r[3] += l;
    S.deg[i] = static_cast<Index>(A.ptr[i + 1] - A.ptr[i]);
  }
  return finish(V, T, kind, scale, with_direction, compress, S);
}

namespace {
// One vertex's ring (see laplacian_local_ring): L_i's components, and l, the sum of the lengths of the
// edges to the neighbours j > i in list order, each also added to elen_j. Masked: every neighbour's
// length is computed and masked to +0 for j < i (adding +0 leaves l and elen_j unchanged: both are
// >= +0, and elen_j of a j < i is no longer read), no branch on j > i; otherwise the branch.
template <bool Masked>
inline void ring_sums(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, Eigen::Index i, double* elen,
                      double& x, double& y, double& z, double& l) {
  x = 0, y = 0, z = 0, l = 0;
  const double xi = V(i, 0), yi = V(i, 1), zi = V(i, 2);
  for (Offset k = A.ptr[i]; k < A.ptr[i + 1]; ++k) {
    const Index j = A.nbr[k];
    const double dx = xi - V(j, 0), dy = yi - V(j, 1), dz = zi - V(j, 2);
    x += dx, y += dy, z += dz;
    if (Masked) {
      const double e = std::sqrt(dx * dx + dy * dy + dz * dz);
      std::uint64_t bits;
      std::memcpy(&bits, &e, sizeof bits);
      bits &= -static_cast<std::uint64_t>(j > i);  // e, or +0 for j < i
      double w;
      std::memcpy(&w, &bits, sizeof w);
      l += w;
      elen[j] += w;
    } else if (j > i) {
      const double e = std::sqrt(dx * dx + dy * dy + dz * dz);
      l += e;
      elen[j] += e;
    }
  }
}

template <bool Masked>
void local_ring(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, LocalRingCarrier& out) {
  const Eigen::Index n = V.rows();
  out.value.resize(n);
  out.ell.resize(n);
  out.elen.setZero(n);
  double* elen = out.elen.data();
  for (Eigen::Index i = 0; i < n; ++i) {
    double x, y, z, l;
    ring_sums<Masked>(V, A, i, elen, x, y, z, l);
    const double deg = static_cast<double>(A.ptr[i + 1] - A.ptr[i]);
    const double ell = (elen[i] + l) / std::max(deg, 1.0);
    out.ell[i] = ell;
    out.value[i] = deg == 0 || !(ell > 0) ? 0.0 : std::sqrt(x * x + y * y + z * z) / ell;  // eq. 7.1.5 / l_i
  }
}
}  // namespace

void laplacian_local_ring(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, LocalRingCarrier& out,
                          bool branch_free) {
  // The same arithmetic, in the same order, as the Local branch of the adjacency overload above:
  // L_i = sum_j (x_i - x_j) over the neighbours in list order (eqs. 7.1.2-7.1.3), d_i = ||L_i||
  // (eq. 7.1.5), l_i = (elen_i + l) / deg_i with elen_i the lengths added by the neighbours j < i (in
  // increasing j) and l those of the neighbours j > i (in list order).
  if (branch_free)
    local_ring<true>(V, A, out);
  else
    local_ring<false>(V, A, out);
}

void laplacian_local_change(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, const LocalRingCarrier& R,
                            const Eigen::VectorXd& d_target, MatrixX3dR& dL) {
  const Eigen::Index n = V.rows();
  dL.setZero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (d_target[i] == R.value[i]) continue;
    // direction_i and gain_i exactly as the adjacency overload forms them (0 where it leaves them 0)
    double dir[3] = {0, 0, 0}, gain = 0;
    const double deg = static_cast<double>(A.ptr[i + 1] - A.ptr[i]), ell = R.ell[i];
    if (!(deg == 0 || !(ell > 0))) {
      double x = 0, y = 0, z = 0;
      const double xi = V(i, 0), yi = V(i, 1), zi = V(i, 2);
      for (Offset k = A.ptr[i]; k < A.ptr[i + 1]; ++k) {
        const Index j = A.nbr[k];
        x += xi - V(j, 0), y += yi - V(j, 1), z += zi - V(j, 2);
      }
      const double d = std::sqrt(x * x + y * y + z * z);  // eq. 7.1.5
      if (d > 0) dir[0] = x / d, dir[1] = y / d, dir[2] = z / d, gain = ell;
    }
    const double s = gain * (d_target[i] - R.value[i]);  // eq. 7.2.19 generalised
    dL(i, 0) = dir[0] * s, dL(i, 1) = dir[1] * s, dL(i, 2) = dir[2] * s;
  }
}

namespace {

LaplacianCarrierField finish(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                             LaplacianCarrier kind, double scale, bool with_direction, double compress,
                             const RingSums& S) {
  const Eigen::Index n = V.rows();
  const bool local = kind != LaplacianCarrier::Thesis && kind != LaplacianCarrier::NormalGlobal;
  const bool normal = kind == LaplacianCarrier::Normal || kind == LaplacianCarrier::CotNormal ||
                      kind == LaplacianCarrier::NormalGlobal;
  const bool cot = kind == LaplacianCarrier::CotLocal || kind == LaplacianCarrier::CotNormal;
  // Triangles: area-weighted normals, cotangent Laplacian C_i and barycentric areas A_i.
  MatrixX3dR N, C;
  Eigen::VectorXd area, W;
  if (normal || cot) {
    N = MatrixX3dR::Zero(n, 3);
    if (cot) C = MatrixX3dR::Zero(n, 3), area = Eigen::VectorXd::Zero(n), W = Eigen::VectorXd::Zero(n);
    for (Eigen::Index f = 0; f < T.rows(); ++f) {
      const Index i0 = T(f, 0), i1 = T(f, 1), i2 = T(f, 2);
      const Eigen::RowVector3d p0 = V.row(i0), p1 = V.row(i1), p2 = V.row(i2);
      const Eigen::RowVector3d cr = (p1 - p0).cross(p2 - p0);
      N.row(i0) += cr, N.row(i1) += cr, N.row(i2) += cr;
      if (!cot) continue;
      const double dbl = cr.norm();  // twice the triangle's area
      if (!(dbl > 0)) continue;
      const Index id[3] = {i0, i1, i2};
      const Eigen::RowVector3d p[3] = {p0, p1, p2};
      for (int c = 0; c < 3; ++c) {
        // the corner c weighs the opposite edge (u, w): cot = (a . b) / |a x b|
        const Index u = id[(c + 1) % 3], w = id[(c + 2) % 3];
        const Eigen::RowVector3d a = p[(c + 1) % 3] - p[c], b = p[(c + 2) % 3] - p[c];
        const double ct = 0.5 * a.dot(b) / dbl;
        const Eigen::RowVector3d duw = p[(c + 1) % 3] - p[(c + 2) % 3];
        C.row(u) += ct * duw, C.row(w) -= ct * duw;
        W[u] += ct, W[w] += ct;
        area[id[c]] += dbl / 6.0;
      }
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      const double len = N.row(i).norm();
      if (len > 0) N.row(i) /= len;
    }
  }

  LaplacianCarrierField out;
  out.value = Eigen::VectorXd::Zero(n);
  if (with_direction) out.direction = MatrixX3dR::Zero(n, 3), out.gain = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (S.deg[i] == 0) continue;
    const double deg = static_cast<double>(S.deg[i]);
    const double* r = S.row(i);
    const double ell = local ? r[3] / deg : scale;  // l_i, or the global unit of the thesis carrier
    if (!(ell > 0)) continue;
    const Eigen::RowVector3d Li(r[0], r[1], r[2]);
    switch (kind) {
      case LaplacianCarrier::Thesis:
      case LaplacianCarrier::Local: {
        const double d = Li.norm();  // eq. 7.1.5
        out.value[i] = d / ell;
        if (with_direction && d > 0) out.direction.row(i) = Li / d, out.gain[i] = ell;
        break;
      }
      case LaplacianCarrier::Normal:
      case LaplacianCarrier::NormalGlobal:
        out.value[i] = Li.dot(N.row(i)) / ell;
        if (with_direction) out.direction.row(i) = N.row(i), out.gain[i] = ell;
        break;
      case LaplacianCarrier::CotLocal:
      case LaplacianCarrier::CotNormal: {
        if (!(area[i] > 0)) break;
        const Eigen::RowVector3d Ci = C.row(i);
        const double u = ell / area[i];
        // dC_i ~ (W_i / deg_i) dL_i when v_i moves against its 1-ring; W_i clamped (obtuse triangles)
        const double g = deg * area[i] / (ell * std::max(W[i], 0.1 * deg));
        if (kind == LaplacianCarrier::CotLocal) {
          const double c = Ci.norm();
          out.value[i] = c * u;
          if (with_direction && c > 0) out.direction.row(i) = Ci / c, out.gain[i] = g;
        } else {
          out.value[i] = Ci.dot(N.row(i)) * u;
          if (with_direction) out.direction.row(i) = N.row(i), out.gain[i] = g;
        }
        break;
      }
    }
    if (compress > 0) {  // g = asinh(s / c), ds/dg = sqrt(s^2 + c^2)
      const double v = out.value[i];
      out.value[i] = std::asinh(v / compress);
      if (with_direction) out.gain[i] *= std::sqrt(v * v + compress * compress);
    }
  }
  return out;
}

}  // namespace

}  // namespace meshmark
