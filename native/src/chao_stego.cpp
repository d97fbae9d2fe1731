// Chao et al. 2009 multi-layer PCA-interval steganography (see chao_stego.h, docs/stego.md).
#include "meshmark/chao_stego.h"
#include "meshmark/error.h"
#include "meshmark/pca.h"

#include <cmath>
#include <string>

namespace meshmark {

namespace {
void check_params(int n_layers, int n_intervals) {
  if (n_layers < 1 || n_layers > 30) throw MeshError("n_layers must be 1..30, got " + std::to_string(n_layers));
  if (n_intervals < 2) throw MeshError("n_intervals must be >= 2, got " + std::to_string(n_intervals));
}

// Move d (layer-j units, interval k) into `target` (the neighbour of k): mirror across their shared
// boundary; a point exactly on a boundary goes to the middle of the target interval.
double mirror_into(double d, double target) {
  const double k = std::floor(d);
  const double B = target > k ? k + 1 : k;  // shared boundary
  double out = 2 * B - d;
  if (std::floor(out) != target) out = target + 0.5;
  return out;
}
}  // namespace

ChaoFrame chao_frame(const Eigen::Ref<const MatrixX3dR>& V) {
  if (V.rows() < 2) throw MeshError("Chao embedding needs at least 2 vertices, got " + std::to_string(V.rows()));
  const PCA P = pca(V);
  ChaoFrame f;
  f.centroid = P.centroid;
  f.axes = P.axes;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d q = P.axes.col(a);
    double lo = 0, hi = 0;
    Index ilo = 0, ihi = 0;
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      const double p = (V.row(i).transpose() - P.centroid).dot(q);
      if (i == 0 || p < lo) { lo = p; ilo = static_cast<Index>(i); }
      if (i == 0 || p > hi) { hi = p; ihi = static_cast<Index>(i); }
    }
    if (!(hi > lo)) throw MeshError("Chao embedding: the mesh is flat along principal axis " + std::to_string(a + 1));
    f.pa[a] = lo;
    f.pb[a] = hi;
    f.ia[a] = ilo;
    f.ib[a] = ihi;
  }
  return f;
}

VectorXi chao_carriers(Eigen::Index n, const ChaoFrame& f) {
  std::vector<std::uint8_t> fixed(static_cast<std::size_t>(n), 0);
  for (int a = 0; a < 3; ++a) {
    if (f.ia[a] >= 0 && f.ia[a] < n) fixed[static_cast<std::size_t>(f.ia[a])] = 1;
    if (f.ib[a] >= 0 && f.ib[a] < n) fixed[static_cast<std::size_t>(f.ib[a])] = 1;
  }
  VectorXi c(n);
  Eigen::Index m = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!fixed[static_cast<std::size_t>(i)]) c[m++] = static_cast<Index>(i);
  c.conservativeResize(m);
  return c;
}

MatrixX3dR chao_embed(const Eigen::Ref<const MatrixX3dR>& V, const ChaoFrame& f, const VectorXb& bits,
                      int n_layers, int n_intervals) {
  check_params(n_layers, n_intervals);
  const VectorXi car = chao_carriers(V.rows(), f);
  const Eigen::Index cap = car.size() * 3 * n_layers;
  if (bits.size() > cap)
    throw MeshError("message of " + std::to_string(bits.size()) + " bits exceeds the Chao capacity of " +
                    std::to_string(cap) + " bits");
  MatrixX3dR out = V;
  Eigen::Index b = 0;
  const double N = n_intervals;
  for (Eigen::Index c = 0; c < car.size() && b < bits.size(); ++c) {
    const Index i = car[c];
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3 && b < bits.size(); ++a) {
      const Eigen::Vector3d q = f.axes.col(a);
      const double len = (f.pb[a] - f.pa[a]) / N;
      const double p = (V.row(i).transpose() - f.centroid).dot(q);
      double d = (p - f.pa[a]) / len;  // layer-1 units, in [0, N]
      double scale = 1;
      int j = 0;
      for (; j < n_layers && b < bits.size(); ++j, ++b, scale *= 2) {
        const double top = N * scale;
        double dj = d * scale;
        double k = std::floor(dj);
        if (k >= top) { k = top - 1; dj = std::nextafter(top, 0.0); }
        if (k < 0) { k = 0; dj = 0; }
        const int want = bits[b] ? 1 : 0;
        if ((static_cast<long long>(k) & 1) == want) { d = dj / scale; continue; }
        double target;
        if (j == 0) {  // nearer boundary, inside [pa, pb]
          const double r = dj - k;
          target = ((r < 0.5 && k > 0) || k == top - 1) ? k - 1 : k + 1;
        } else {  // sibling inside the layer j-1 interval
          target = (static_cast<long long>(k) & 1) ? k - 1 : k + 1;
        }
        d = mirror_into(dj, target) / scale;
      }
      // Keep the final position away from the boundaries of its finest interval (float round trip).
      const double s_last = scale / 2;  // the scale of the last layer written
      double dl = d * s_last;
      const double kl = std::floor(dl);
      const double rl = dl - kl;
      if (rl < 1e-6 || rl > 1 - 1e-6) d = (kl + 0.5) / s_last;
      const double p2 = f.pa[a] + d * len;
      delta += (p2 - p) * q;
    }
    out.row(i) += delta.transpose();
  }
  return out;
}

VectorXb chao_extract(const Eigen::Ref<const MatrixX3dR>& V, const ChaoFrame& f, Eigen::Index nbits,
                      int n_layers, int n_intervals) {
  check_params(n_layers, n_intervals);
  const VectorXi car = chao_carriers(V.rows(), f);
  const Eigen::Index cap = car.size() * 3 * n_layers;
  if (nbits < 0 || nbits > cap)
    throw MeshError("nbits " + std::to_string(nbits) + " exceeds the Chao capacity of " + std::to_string(cap) + " bits");
  VectorXb bits(nbits);
  Eigen::Index b = 0;
  const double N = n_intervals;
  for (Eigen::Index c = 0; c < car.size() && b < nbits; ++c) {
    const Index i = car[c];
    for (int a = 0; a < 3 && b < nbits; ++a) {
      const Eigen::Vector3d q = f.axes.col(a);
      const double len = (f.pb[a] - f.pa[a]) / N;
      const double d = ((V.row(i).transpose() - f.centroid).dot(q) - f.pa[a]) / len;
      double scale = 1;
      for (int j = 0; j < n_layers && b < nbits; ++j, ++b, scale *= 2) {
        double k = std::floor(d * scale);
        if (k >= N * scale) k = N * scale - 1;
        if (k < 0) k = 0;
        bits[b] = static_cast<std::uint8_t>(static_cast<long long>(k) & 1);
      }
    }
  }
  return bits;
}

}  // namespace meshmark
