#include "meshmark/mesh.h"

namespace meshmark {

Polygons Polygons::from_triangles(const MatrixX3iR& T) {
  Polygons P;
  const Offset m = T.rows();
  P.indices.resize(3 * m);
  P.offsets.resize(m + 1);
  for (Offset f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) P.indices[3 * f + k] = T(f, k);
  for (Offset f = 0; f <= m; ++f) P.offsets[f] = 3 * f;
  return P;
}

}  // namespace meshmark
