#include "meshmark/pca_min_corner_normalize.h"
#include "meshmark/error.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace meshmark {

MatrixX3dR pca_min_corner_normalize(const Eigen::Ref<const MatrixX3dR>& V) {
  using LD = long double;
  using V3 = Eigen::Matrix<LD, 3, 1>;
  using M3 = Eigen::Matrix<LD, 3, 3>;
  const Eigen::Index n = V.rows();
  auto finite = [&](Eigen::Index i) { return std::isfinite(V(i, 0)) && std::isfinite(V(i, 1)) && std::isfinite(V(i, 2)); };
  V3 c = V3::Zero();
  Eigen::Index m = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (finite(i)) c += V.row(i).transpose().cast<LD>(), ++m;
  if (m == 0) throw MeshError("the mesh has no finite vertex");
  c /= static_cast<LD>(m);
  M3 C = M3::Zero();
  for (Eigen::Index i = 0; i < n; ++i)
    if (finite(i)) {
      const V3 d = V.row(i).transpose().cast<LD>() - c;
      C.noalias() += d * d.transpose();
    }
  Eigen::SelfAdjointEigenSolver<M3> es(C);  // the right singular vectors of the centred rows (svd in pca.m)
  Eigen::Matrix3d Q;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d q = es.eigenvectors().col(2 - k).normalized().cast<double>();  // descending variance
    if (q.maxCoeff() < std::abs(q.minCoeff())) q = -q;  // pca.m: max(coeff) < abs(min(coeff)) -> flip
    Q.col(k) = q;
  }
  MatrixX3dR P = V * Q;  // vertex' * trans (uncentred)
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (Eigen::Index i = 0; i < n; ++i)
    if (finite(i)) lo = lo.cwiseMin(P.row(i)), hi = hi.cwiseMax(P.row(i));
  const double range = (hi - lo).maxCoeff();
  if (!(range > 0)) throw MeshError("all vertices coincide: the mesh cannot be normalised");
  for (Eigen::Index i = 0; i < n; ++i) P.row(i) = (P.row(i) - lo) / range;
  return P;
}

}  // namespace meshmark
