// meshmark: the normal degradation curve dis(M, M^t) of thesis ch. 3 (eq. 3.2.2) over many levels t.
#pragma once
#include "meshmark/mesh.h"

#include <cstdint>

namespace meshmark {

struct NormalDegradationSweep {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> mean;      // (k,3) dis per level: mean, area, dihedral
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> variance;  // (k,3) variance over the repeats (0 if 1)
  Eigen::VectorXd excluded;  // (k,) mean fraction of triangles excluded (zero or non-finite normal)
};

// For each level t[j] (0..64) and each repeat r: M^t = dithered_quantize(V, t, s, Float64) (the 64 - t
// least significant bits of the IEEE-754 pattern of every coordinate random, §3.2.1) with the seed
// s = sweep_seed(seed, t, r), and dis(M, M^t) (eq. 3.2.2) with the three weightings of eq. 3.2.3
// (mean; area in M; Gaussian of the smallest dihedral angle, mu and sigma in degrees), computed once
// per sample by normal_degradation. A sample whose weights are all 0 contributes NaN.
// MeshError if a level is outside 0..64, repeats < 1, or sigma <= 0.
NormalDegradationSweep normal_degradation_sweep(const Eigen::Ref<const MatrixX3dR>& V,
                                                const Eigen::Ref<const MatrixX3iR>& T, const Eigen::Ref<const VectorXi>& t,
                                                std::uint64_t seed, int repeats, double mu = 0.0, double sigma = 3.5);

// The seed of sample (t, r): a splitmix64 mix of seed, t and r (independent of the other levels asked for).
std::uint64_t sweep_seed(std::uint64_t seed, int t, int r);

}  // namespace meshmark
