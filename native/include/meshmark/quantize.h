// meshmark: uniform coordinate quantization (the quantization attack of thesis 6.3.2).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// Per axis a: lo = min, hi = max over the rows of V, step = (hi - lo) / 2^bits, and
//   x' = lo + step * round((x - lo) / step)       (ties round down)
// i.e. every coordinate snaps to the nearest of the 2^bits + 1 grid points lo + k step; the error
// is at most step / 2. An axis with hi == lo is unchanged. MeshError unless 1 <= bits <= 52.
MatrixX3dR quantize(const Eigen::Ref<const MatrixX3dR>& V, int bits);

}  // namespace meshmark
