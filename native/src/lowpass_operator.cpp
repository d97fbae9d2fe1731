#include "meshmark/lowpass_operator.h"
#include "meshmark/error.h"

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <cmath>
#include <vector>
#ifdef MESHMARK_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace meshmark {

struct LowpassOperator::Solver {
#ifdef MESHMARK_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> chol;
#else
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> chol;
#endif
};

LowpassOperator::LowpassOperator(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                 double t, int k)
    : solver_(std::make_unique<Solver>()), k_(k) {
  const Eigen::Index n = V.rows();
  if (n == 0 || T.rows() == 0) throw MeshError("low-pass operator: the mesh has no triangles");
  if (!(t > 0) || !std::isfinite(t)) throw MeshError("low-pass operator: t must be a positive number");
  if (k < 1 || k > 8) throw MeshError("low-pass operator: the power k must be in 1..8");
  if (T.minCoeff() < 0 || T.maxCoeff() >= n) throw MeshError("low-pass operator: a triangle index is out of range");
  mass_.setZero(n);
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<size_t>(T.rows()) * 9 + static_cast<size_t>(n));
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    const Index c[3] = {T(f, 0), T(f, 1), T(f, 2)};
    const Eigen::Vector3d p[3] = {V.row(c[0]).transpose(), V.row(c[1]).transpose(), V.row(c[2]).transpose()};
    const double area2 = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (!(area2 > 0) || !std::isfinite(area2)) continue;
    for (int a = 0; a < 3; ++a) mass_[c[a]] += area2 / 6.0;
    for (int a = 0; a < 3; ++a) {  // the angle at corner a is opposite the edge (b, d)
      const int b = (a + 1) % 3, d = (a + 2) % 3;
      const Eigen::Vector3d u = p[b] - p[a], v = p[d] - p[a];
      const double w = 0.5 * u.dot(v) / u.cross(v).norm();  // cot / 2
      trip.emplace_back(c[b], c[d], -w);
      trip.emplace_back(c[d], c[b], -w);
      trip.emplace_back(c[b], c[b], w);
      trip.emplace_back(c[d], c[d], w);
    }
  }
  Eigen::Index ref = 0;
  double total = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (mass_[i] > 0) ++ref, total += mass_[i];
  if (ref == 0) throw MeshError("low-pass operator: every triangle has a zero area");
  const double mean = total / static_cast<double>(ref);
  Eigen::SparseMatrix<double> A(n, n);
  for (auto& e : trip) e = Eigen::Triplet<double>(e.row(), e.col(), t * e.value());
  inv_sqrt_mass_.setZero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    mass_[i] /= mean;
    trip.emplace_back(i, i, mass_[i] > 0 ? mass_[i] : 1.0);
    if (mass_[i] > 0) inv_sqrt_mass_[i] = 1.0 / std::sqrt(mass_[i]);
  }
  A.setFromTriplets(trip.begin(), trip.end());
#ifdef MESHMARK_HAVE_CHOLMOD
  solver_->chol.cholmod().nmethods = 1;
  solver_->chol.cholmod().method[0].ordering = CHOLMOD_AMD;
#endif
  solver_->chol.compute(A);
  if (solver_->chol.info() != Eigen::Success) throw MeshError("low-pass operator: M + t L could not be factorised");
}

LowpassOperator::~LowpassOperator() = default;

Eigen::MatrixXd LowpassOperator::apply(const Eigen::Ref<const Eigen::MatrixXd>& W) const {
  if (W.rows() != mass_.size()) throw MeshError("low-pass operator: the input has the wrong number of rows");
  Eigen::MatrixXd X = inv_sqrt_mass_.asDiagonal() * W;
  for (int s = 0; s < k_; ++s) {
    Eigen::MatrixXd B = mass_.asDiagonal() * X;
    X = solver_->chol.solve(B);
  }
  return X;
}

Eigen::MatrixXd LowpassOperator::apply_transpose(const Eigen::Ref<const Eigen::MatrixXd>& R) const {
  if (R.rows() != mass_.size()) throw MeshError("low-pass operator: the input has the wrong number of rows");
  Eigen::MatrixXd X = R;
  for (int s = 0; s < k_; ++s) {
    Eigen::MatrixXd B = solver_->chol.solve(X);
    X = mass_.asDiagonal() * B;
  }
  return inv_sqrt_mass_.asDiagonal() * X;
}

}  // namespace meshmark
