// meshmark: the low-pass operator that shapes informed tracing's keyed patterns (docs/tracing.md).
#pragma once
#include "meshmark/mesh.h"

#include <memory>

namespace meshmark {

// H = (A^-1 M)^k M^-1/2 and its transpose H^T = M^-1/2 (M A^-1)^k, with A = M + t L:
//   M: lumped mass (a third of the area of each incident triangle), divided by its mean over the
//      referenced vertices (so t is in units of the mean vertex area and the cut-off mode of
//      (1 + t mu)^-k lies near n / (4 pi t) by Weyl's law);
//   L: the cotangent stiffness matrix (P1 finite elements: sum over triangles of (cot / 2) on each
//      edge; positive semi-definite for any triangulation), triangles with a zero area skipped.
// A is factorised once (CHOLMOD supernodal Cholesky when built with it, else Eigen's simplicial LLT).
// Rows of unreferenced vertices (zero mass) are identity rows of A and zero rows of H and H^T.
class LowpassOperator {
 public:
  LowpassOperator(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T, double t, int k);
  ~LowpassOperator();
  LowpassOperator(const LowpassOperator&) = delete;
  LowpassOperator& operator=(const LowpassOperator&) = delete;

  Eigen::MatrixXd apply(const Eigen::Ref<const Eigen::MatrixXd>& W) const;            // H W, W (n, c)
  Eigen::MatrixXd apply_transpose(const Eigen::Ref<const Eigen::MatrixXd>& R) const;  // H^T R, R (n, c)
  const Eigen::VectorXd& mass() const { return mass_; }                            // (n,) normalised M
  Eigen::Index size() const { return mass_.size(); }

 private:
  struct Solver;
  std::unique_ptr<Solver> solver_;
  Eigen::VectorXd mass_, inv_sqrt_mass_;
  int k_ = 1;
};

}  // namespace meshmark
