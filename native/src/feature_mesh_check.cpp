#include "meshmark/feature_mesh_check.h"
#include "meshmark/error.h"

#include <string>

namespace meshmark {

VectorXb feature_mesh_check(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T) {
  const Index n = static_cast<Index>(V.rows());
  VectorXb used = VectorXb::Zero(n);
  int count = 0;
  for (Eigen::Index f = 0; f < T.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index v = T(f, k);
      if (v < 0 || v >= n)
        throw MeshError("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) + ", out of range");
      if (!used[v]) used[v] = 1, ++count;
    }
  if (T.rows() < 1 || count < 4)
    throw MeshError("mesh too small for steganalysis features: need at least 4 vertices used by triangles, got " +
                    std::to_string(count));
  return used;
}

}  // namespace meshmark
