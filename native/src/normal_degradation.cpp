#include "meshmark/normal_degradation.h"
#include "meshmark/error.h"
#include "meshmark/unique_edges.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace meshmark {

namespace {
// unnormalized face normals (b - a) x (c - a)
MatrixX3dR raw_normals(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  MatrixX3dR N(T.rows(), 3);
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Eigen::Vector3d a = V.row(T(f, 0)), b = V.row(T(f, 1)), c = V.row(T(f, 2));
    N.row(f) = (b - a).cross(c - a).transpose();
  }
  return N;
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {  // in [0, pi]
  return std::atan2(a.cross(b).norm(), a.dot(b));
}
}  // namespace

Eigen::VectorXd min_dihedral_angles_deg(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Eigen::Index t = T.rows();
  const MatrixX3dR N = raw_normals(V, T);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(t, std::numeric_limits<double>::infinity());
  // group the triangle sides by undirected edge (sort by key), then pair every two faces of an edge
  std::vector<std::pair<std::uint64_t, Index>> sides;
  sides.reserve(static_cast<size_t>(3 * t));
  for (Eigen::Index f = 0; f < t; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = static_cast<std::uint32_t>(T(f, k)), b = static_cast<std::uint32_t>(T(f, (k + 1) % 3));
      sides.emplace_back(std::min(a, b) << 32 | std::max(a, b), static_cast<Index>(f));
    }
  std::sort(sides.begin(), sides.end());
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    while (j < sides.size() && sides[j].first == sides[i].first) ++j;
    for (size_t p = i; p < j; ++p)
      for (size_t q = p + 1; q < j; ++q) {
        const Index f = sides[p].second, g = sides[q].second;
        if (f == g) continue;
        const Eigen::Vector3d nf = N.row(f), ng = N.row(g);
        if (nf.squaredNorm() == 0 || ng.squaredNorm() == 0) continue;
        const double ang = angle_between(nf, ng) * 180.0 / M_PI;
        x[f] = std::min(x[f], ang);
        x[g] = std::min(x[g], ang);
      }
    i = j;
  }
  return x;
}

NormalDegradation normal_degradation(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3dR>& V2,
                                     const Eigen::Ref<const MatrixX3iR>& T, NormalWeighting weighting, double mu,
                                     double sigma) {
  if (V.rows() != V2.rows())
    throw MeshError("normal degradation compares meshes with the same faces: " + std::to_string(V.rows()) + " and " +
                    std::to_string(V2.rows()) + " vertices");
  if (weighting == NormalWeighting::Dihedral && !(sigma > 0)) throw MeshError("sigma must be > 0");
  const Eigen::Index t = T.rows();
  const MatrixX3dR N1 = raw_normals(V, T), N2 = raw_normals(V2, T);
  NormalDegradation out;
  out.angle = Eigen::VectorXd::Zero(t);
  out.weight = Eigen::VectorXd::Zero(t);
  Eigen::VectorXd x;
  if (weighting == NormalWeighting::Dihedral) x = min_dihedral_angles_deg(V, T);
  const double gnorm = 1.0 / std::sqrt(2 * M_PI * sigma * sigma);
  double sw = 0, swa = 0;
  for (Eigen::Index f = 0; f < t; ++f) {
    Eigen::Vector3d a = N1.row(f), b = N2.row(f);
    const double la = a.norm(), lb = b.norm();
    if (!(la > 0) || !(lb > 0) || !std::isfinite(la) || !std::isfinite(lb)) {
      ++out.n_excluded;
      continue;
    }
    out.angle[f] = angle_between(a / la, b / lb);  // the smaller angle, radians (eq. 3.2.2)
    double w = 1.0;
    if (weighting == NormalWeighting::Area) w = 0.5 * la;
    else if (weighting == NormalWeighting::Dihedral)  // eq. 3.2.3, x_i in degrees
      w = std::isfinite(x[f]) ? gnorm * std::exp(-(x[f] - mu) * (x[f] - mu) / (2 * sigma * sigma)) : 0.0;
    out.weight[f] = w;
    sw += w;
    swa += w * out.angle[f];
  }
  out.value = sw > 0 ? swa / sw : std::numeric_limits<double>::quiet_NaN();  // eq. 3.2.2
  return out;
}

}  // namespace meshmark
